#pragma once
// Fragment catalogue of a particle state: mirrors a half model first, then writes
// PREFIX.csv, PREFIX.h5 and PREFIX.pkdgrav and logs the largest fragments.

#include <filesystem>

#include "shatter/core/particles.hpp"
#include "shatter/fracture/fragments.hpp"

namespace shatter::cli {

FragmentCatalogue report_fragments(const ParticleStore& particles, int symmetry_axis,
                                   const FragmentSearchSpec& spec,
                                   const std::filesystem::path& prefix);

}  // namespace shatter::cli
