#pragma once
// The /particles and /groups layout shared by snapshots and checkpoints.

#include <hdf5.h>

#include <functional>
#include <string_view>

#include "shatter/core/particles.hpp"
#include "shatter/io/columns.hpp"

namespace shatter::io {

// `after_column` (optional) is called with each dataset's name once it is written.
void write_particles(hid_t file, const ParticleStore& store, const ColumnSelection& columns,
                     const std::function<void(std::string_view)>& after_column = {});
ParticleStore read_particles(hid_t file);
ColumnSelection columns_in_file(hid_t file);
std::size_t particles_in_file(hid_t file);

}  // namespace shatter::io
