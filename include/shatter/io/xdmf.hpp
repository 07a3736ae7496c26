#pragma once
// XDMF (version 3) sidecar: one .xmf file describing all snapshots of a run as a temporal
// collection of Polyvertex grids (one vertex cell per particle): positions as XYZ geometry,
// velocity a Vector, stress a Tensor6, every other column a Scalar attribute, the data left in the
// HDF5 files. ParaView's default Xdmf3 reader (and the legacy XDMF reader, and meshio) opens it as
// a time series (tests/python/test_xdmf_paraview.py checks this with ParaView's own reader).

#include <cstddef>
#include <filesystem>
#include <set>
#include <string>
#include <string_view>
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

// The XDMF document for `entries` (in the order given). Each grid's vertex cells (connectivity
// 0..n-1) are read from the dataset xdmf_cells_dataset(n) of `cells_file` (relative to the .xmf).
std::string xdmf_document(const std::vector<XdmfEntry>& entries, std::string_view cells_file);
// The path inside the cells file of the connectivity of an n-point grid ("cells/n<n>").
std::string xdmf_cells_dataset(std::size_t n);

// Keeps the list of a run's snapshots and rewrites the .xmf file (atomically) on each addition,
// so the sidecar is valid while the run is going and after a crash. The vertex cells live in
// one HDF5 file beside it (particles.xmf -> particles_cells.h5), written once per run.
class XdmfSeries {
 public:
  explicit XdmfSeries(std::filesystem::path xmf) : xmf_(std::move(xmf)) {}

  // Registers a written snapshot and rewrites the sidecar.
  void add(const std::filesystem::path& snapshot);
  // Rebuilds the list from snapshot files (on resume), keeping those with time <= `until`.
  void rebuild(const std::vector<std::filesystem::path>& snapshots, double until);

  const std::vector<XdmfEntry>& entries() const { return entries_; }
  const std::filesystem::path& path() const { return xmf_; }
  // The shared connectivity file beside the .xmf file.
  std::filesystem::path cells_path() const;

 private:
  void write();
  void write_cells();
  XdmfEntry entry_for(const std::filesystem::path& snapshot) const;

  std::filesystem::path xmf_;
  std::vector<XdmfEntry> entries_;
  std::set<std::size_t> cells_written_;  // the particle counts in the cells file
};

}  // namespace shatter::io
