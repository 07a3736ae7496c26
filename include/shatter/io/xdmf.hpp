#pragma once
// XDMF (version 3) sidecar: one .xmf file describing all snapshots of a run as a temporal
// collection of Polyvertex grids: positions as XYZ geometry, velocity a Vector, stress a Tensor6,
// every other column a Scalar attribute, the data left in the HDF5 files. ParaView's default
// Xdmf3 reader (and the legacy XDMF reader, and meshio) opens it as a time series
// (tests/python/test_xdmf_paraview.py checks this with ParaView's own reader).

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "shatter/io/columns.hpp"
#include "shatter/io/snapshot.hpp"

namespace shatter::io {

struct XdmfEntry {
  std::string file;  // snapshot path relative to the .xmf file
  double time = 0.0;
  std::size_t particles = 0;
  std::vector<SnapshotDataset> datasets;  // must include position (or x, y, z)
};

// The XDMF document for `entries` (in the order given).
std::string xdmf_document(const std::vector<XdmfEntry>& entries);

// Keeps the list of a run's snapshots and rewrites the .xmf file (atomically) on each addition,
// so the sidecar is valid while the run is going and after a crash.
class XdmfSeries {
 public:
  explicit XdmfSeries(std::filesystem::path xmf) : xmf_(std::move(xmf)) {}

  // Registers a written snapshot and rewrites the sidecar.
  void add(const std::filesystem::path& snapshot);
  // Rebuilds the list from snapshot files (on resume), keeping those with time <= `until`.
  void rebuild(const std::vector<std::filesystem::path>& snapshots, double until);

  const std::vector<XdmfEntry>& entries() const { return entries_; }
  const std::filesystem::path& path() const { return xmf_; }

 private:
  void write() const;
  XdmfEntry entry_for(const std::filesystem::path& snapshot) const;

  std::filesystem::path xmf_;
  std::vector<XdmfEntry> entries_;
};

}  // namespace shatter::io
