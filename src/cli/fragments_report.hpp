#pragma once
// Fragment catalogue of a particle state: mirrors a half model first, then writes PREFIX.csv,
// PREFIX.h5 (with each fragment's mass from each body and material when the names are known) and
// PREFIX.ss (pkdgrav's binary format, one particle per fragment; with `ss_particles` also
// PREFIX_particles.ss, one per point) and logs the largest fragments.

#include <filesystem>
#include <string>
#include <vector>

#include "shatter/core/particles.hpp"
#include "shatter/fracture/fragments.hpp"

namespace shatter::cli {

struct FragmentReportInfo {
  double time = 0.0;                        // s, written into the ss files
  std::vector<std::string> body_names;      // per body index; empty = no composition columns
  std::vector<std::string> body_materials;  // material name of each body
  bool ss_particles = false;                // also write PREFIX_particles.ss
};

FragmentCatalogue report_fragments(const ParticleStore& particles, int symmetry_axis,
                                   const FragmentSearchSpec& spec,
                                   const std::filesystem::path& prefix,
                                   const FragmentReportInfo& info = {});

}  // namespace shatter::cli
