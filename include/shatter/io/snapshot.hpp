#pragma once
// HDF5 snapshots: one file per output time, one 1-d dataset per particle column under
// /particles (attribute "units"), the material groups under /groups, and the time, step and
// units as attributes of the root. Written through a temporary file, so a snapshot that exists
// is complete.

#include <cstdint>
#include <filesystem>
#include <string>

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
};

void write_snapshot(const std::filesystem::path& file, const ParticleStore& store,
                    const SnapshotHeader& header, const ColumnSelection& columns);

struct Snapshot {
  ParticleStore particles;  // only the columns the file holds
  SnapshotHeader header;
};

// Throws std::runtime_error naming the file when it is missing, truncated or not a snapshot.
Snapshot read_snapshot(const std::filesystem::path& file);

// Time, step and columns of a snapshot without reading the particle data.
struct SnapshotInfo {
  SnapshotHeader header;
  std::size_t particles = 0;
  ColumnSelection columns;
};
SnapshotInfo inspect_snapshot(const std::filesystem::path& file);

}  // namespace shatter::io
