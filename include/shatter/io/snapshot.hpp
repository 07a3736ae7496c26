#pragma once
// HDF5 snapshots: one file per output time. Under /particles one dataset per column (attribute
// "units"), except that positions, velocities and the stress are N x 3, N x 3 and N x 6 datasets
// "position", "velocity" and "stress" (attribute "components"; the stress in XDMF's Tensor6
// order xx, xy, xz, yy, yz, zz) so that XDMF readers see vectors and a tensor. The material
// groups are under /groups, the body and material names under /names, and the time, step and
// units are attributes of the root. Datasets are chunked, shuffled and deflated; reals are
// binary64 or, on request, binary32. Written through a temporary file, so a snapshot that exists
// is complete. docs/outputs.md describes the layout.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "shatter/core/particles.hpp"
#include "shatter/io/columns.hpp"

namespace shatter::io {

struct SnapshotHeader {
  double time = 0.0;  // s
  std::uint64_t step = 0;
  std::string program_version;
  // Axis of the symmetry plane through the origin (0, 1, 2; -1 = none): the file holds the
  // positive half, post-processing mirrors it.
  int symmetry_axis = -1;
  // Read: false for a snapshot written before the header was checksummed (format 1, read with a
  // warning); a newer snapshot whose header does not match its checksum is refused.
  bool checksummed = true;
};

// What a snapshot stores besides the header and the columns, and how.
struct SnapshotOptions {
  bool single_precision = false;  // reals as IEEE binary32 (checkpoints are always binary64)
  // Name of each body (index = the particles' "body" value) and of each material (index = a
  // group's material); empty = not known (not written).
  std::vector<std::string> body_names;
  std::vector<std::string> material_names;
};

void write_snapshot(const std::filesystem::path& file, const ParticleStore& store,
                    const SnapshotHeader& header, const ColumnSelection& columns,
                    const SnapshotOptions& options = {});

struct Snapshot {
  ParticleStore particles;  // only the columns the file holds
  SnapshotHeader header;
  std::vector<std::string> body_names;      // empty for snapshots without names
  std::vector<std::string> material_names;  // per material index
};

// Throws std::runtime_error naming the file when it is missing, truncated or not a snapshot.
Snapshot read_snapshot(const std::filesystem::path& file);

// Time, step and columns of a snapshot without reading the particle data.
// One dataset of /particles as stored.
struct SnapshotDataset {
  std::string name;
  std::size_t components = 1;  // columns of the dataset (1, 3 or 6)
  bool real = true;
  std::size_t bytes = 8;  // per value
  std::string units;
  std::string xdmf_type;  // Scalar, Vector or Tensor6
};
struct SnapshotInfo {
  SnapshotHeader header;
  std::size_t particles = 0;
  ColumnSelection columns;
  std::vector<SnapshotDataset> datasets;
};
SnapshotInfo inspect_snapshot(const std::filesystem::path& file);

}  // namespace shatter::io
