#pragma once
// XDMF (version 2) sidecar: one .xmf file describing all snapshots of a run as a temporal
// collection of Polyvertex grids, every column an attribute, the data left in the HDF5 files.
// ParaView (Xdmf Reader) opens it as a time series.

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "shatter/io/columns.hpp"

namespace shatter::io {

struct XdmfEntry {
  std::string file;  // snapshot path relative to the .xmf file
  double time = 0.0;
  std::size_t particles = 0;
  ColumnSelection columns;  // must include x, y, z
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
