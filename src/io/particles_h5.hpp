#pragma once
// The /particles and /groups layout shared by snapshots and checkpoints.
//
// Checkpoints hold one 1-d dataset per column. Snapshots (the files ParaView, meshio and the
// Python package read) bundle the components of vectors and of the stress into 2-d datasets:
// /particles/position and /particles/velocity (N x 3) and /particles/stress (N x 6, in XDMF's
// Tensor6 order xx, xy, xz, yy, yz, zz); the attribute "components" of each names its columns.
// The readers accept both layouts.

#include <hdf5.h>

#include <functional>
#include <string_view>
#include <vector>

#include "io/h5.hpp"
#include "shatter/core/particles.hpp"
#include "shatter/io/columns.hpp"

namespace shatter::io {

// Columns written as the columns of one 2-d dataset.
struct Bundle {
  std::string_view name;
  std::vector<Field> components;  // in dataset column order
  std::string_view labels;        // the "components" attribute
  std::string_view xdmf_type;     // XDMF AttributeType
};
const std::vector<Bundle>& bundles();
const Bundle* bundle_by_name(std::string_view name);

struct ParticleLayout {
  bool bundle = false;  // vectors and stress as 2-d datasets (snapshots)
  h5::Storage storage;  // compression and precision of the datasets
};

// `after_column` (optional) is called with each dataset's name once it is written.
void write_particles(hid_t file, const ParticleStore& store, const ColumnSelection& columns,
                     const std::function<void(std::string_view)>& after_column = {},
                     const ParticleLayout& layout = {});
// `verify`: whether every dataset must carry a checksum (files that declare checksums).
ParticleStore read_particles(hid_t file, h5::Verify verify = h5::Verify::if_present);
// The columns a file holds (a bundle counts as its components).
ColumnSelection columns_in_file(hid_t file);
std::size_t particles_in_file(hid_t file);

}  // namespace shatter::io
