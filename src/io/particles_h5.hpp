#pragma once
// The /particles and /groups layout shared by snapshots and checkpoints.

#include <hdf5.h>

#include <functional>
#include <string_view>

#include "io/h5.hpp"
#include "shatter/core/particles.hpp"
#include "shatter/io/columns.hpp"

namespace shatter::io {

// `after_column` (optional) is called with each dataset's name once it is written.
void write_particles(hid_t file, const ParticleStore& store, const ColumnSelection& columns,
                     const std::function<void(std::string_view)>& after_column = {});
// `verify`: whether every dataset must carry a checksum (files that declare checksums).
ParticleStore read_particles(hid_t file, h5::Verify verify = h5::Verify::if_present);
ColumnSelection columns_in_file(hid_t file);
std::size_t particles_in_file(hid_t file);

}  // namespace shatter::io
