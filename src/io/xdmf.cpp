#include "shatter/io/xdmf.hpp"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <set>
#include <stdexcept>

#include <fmt/format.h>

#include "io/h5.hpp"
#include "shatter/io/atomic_file.hpp"
#include "shatter/io/snapshot.hpp"

namespace shatter::io {
namespace {

// HDF5 paths never contain XML metacharacters in our layout, but file names might.
std::string xml_escape(std::string_view s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string data_item(const XdmfEntry& e, const SnapshotDataset& d) {
  const std::string dims = d.components == 1 ? fmt::format("{}", e.particles)
                                             : fmt::format("{} {}", e.particles, d.components);
  return fmt::format(
      "          <DataItem Dimensions=\"{}\" NumberType=\"{}\" Precision=\"{}\" "
      "Format=\"HDF\">{}:/particles/{}</DataItem>\n",
      dims, d.real ? "Float" : "Int", d.bytes, xml_escape(e.file), d.name);
}

// The vertex-cell connectivity of an n-point grid (0 .. n-1) in the shared cells file.
std::string cells_item(std::string_view cells_file, std::size_t n) {
  return fmt::format(
      "          <DataItem Dimensions=\"{} 1\" NumberType=\"Int\" Precision=\"8\" "
      "Format=\"HDF\">{}:/{}</DataItem>\n",
      n, xml_escape(cells_file), xdmf_cells_dataset(n));
}

const SnapshotDataset* find(const XdmfEntry& e, std::string_view name) {
  for (const SnapshotDataset& d : e.datasets) {
    if (d.name == name) return &d;
  }
  return nullptr;
}

}  // namespace

std::string xdmf_cells_dataset(std::size_t n) {
  return fmt::format("cells/n{}", n);
}

std::string xdmf_document(const std::vector<XdmfEntry>& entries, std::string_view cells_file) {
  std::string doc =
      "<?xml version=\"1.0\" ?>\n"
      "<Xdmf Version=\"3.0\">\n"
      "  <Domain>\n"
      "    <Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (const XdmfEntry& e : entries) {
    doc += fmt::format("      <Grid Name=\"{}\" GridType=\"Uniform\">\n",
                       xml_escape(std::filesystem::path(e.file).stem().string()));
    doc += fmt::format("        <Time Value=\"{}\" />\n", e.time);
    // One vertex cell per particle with explicit connectivity: without it ParaView's readers build
    // no cells (the default Surface and the Points views show nothing) and meshio has no cells.
    doc += fmt::format(
        "        <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"{}\" "
        "NodesPerElement=\"1\">\n",
        e.particles);
    doc += cells_item(cells_file, e.particles);
    doc += "        </Topology>\n";
    // Positions as one N x 3 dataset (XYZ), which both of ParaView's XDMF readers show; snapshots
    // written before the bundled layout have three 1-d datasets (X_Y_Z, legacy reader only).
    std::vector<std::string_view> geometry;
    if (const SnapshotDataset* p = find(e, "position"); p != nullptr && p->components == 3) {
      doc += "        <Geometry GeometryType=\"XYZ\">\n";
      doc += data_item(e, *p);
      geometry = {"position"};
    } else {
      doc += "        <Geometry GeometryType=\"X_Y_Z\">\n";
      for (std::string_view axis : {"x", "y", "z"}) {
        const SnapshotDataset* a = find(e, axis);
        if (a == nullptr) {
          throw std::invalid_argument(
              fmt::format("snapshot {} lacks positions ('position' or '{}') needed for XDMF "
                          "geometry",
                          e.file, axis));
        }
        doc += data_item(e, *a);
      }
      geometry = {"x", "y", "z"};
    }
    doc += "        </Geometry>\n";
    // Units as Information elements of the grid, not of each Attribute: meshio refuses an
    // Attribute with any child but its DataItem.
    for (const SnapshotDataset& d : e.datasets) {
      if (std::find(geometry.begin(), geometry.end(), d.name) != geometry.end()) continue;
      doc += fmt::format("        <Information Name=\"units:{}\" Value=\"{}\" />\n",
                         xml_escape(d.name), xml_escape(d.units));
    }
    for (const SnapshotDataset& d : e.datasets) {
      if (std::find(geometry.begin(), geometry.end(), d.name) != geometry.end()) continue;
      doc += fmt::format("        <Attribute Name=\"{}\" AttributeType=\"{}\" Center=\"Node\">\n",
                         xml_escape(d.name), d.xdmf_type);
      doc += data_item(e, d);
      doc += "        </Attribute>\n";
    }
    doc += "      </Grid>\n";
  }
  doc += "    </Grid>\n  </Domain>\n</Xdmf>\n";
  return doc;
}

XdmfEntry XdmfSeries::entry_for(const std::filesystem::path& snapshot) const {
  const SnapshotInfo info = inspect_snapshot(snapshot);
  const auto base = xmf_.has_parent_path() ? xmf_.parent_path() : std::filesystem::path(".");
  XdmfEntry e;
  e.file = std::filesystem::relative(snapshot, base).generic_string();
  e.time = info.header.time;
  e.particles = info.particles;
  e.datasets = info.datasets;
  return e;
}

void XdmfSeries::add(const std::filesystem::path& snapshot) {
  entries_.push_back(entry_for(snapshot));
  write();
}

void XdmfSeries::rebuild(const std::vector<std::filesystem::path>& snapshots, double until) {
  entries_.clear();
  for (const auto& s : snapshots) {
    XdmfEntry e = entry_for(s);
    if (e.time <= until) entries_.push_back(std::move(e));
  }
  std::stable_sort(entries_.begin(), entries_.end(),
                   [](const XdmfEntry& a, const XdmfEntry& b) { return a.time < b.time; });
  write();
}

std::filesystem::path XdmfSeries::cells_path() const {
  std::filesystem::path p = xmf_;
  p.replace_extension();
  p += "_cells.h5";
  return p;
}

// The shared connectivity file holds one dataset per distinct particle count (a run has one), so
// it is written once per run, not once per snapshot; rewritten (atomically) when a new count
// appears or on the first write after a restart.
void XdmfSeries::write_cells() {
  std::set<std::size_t> counts;
  for (const XdmfEntry& e : entries_) counts.insert(e.particles);
  if (counts == cells_written_) return;
  const std::filesystem::path file = cells_path();
  h5::QuietErrors quiet;
  h5::write_file_atomically(file, [&](hid_t f) {
    h5::set_attr(f, "format", std::string_view("shatter-xdmf-cells"));
    h5::set_attr(f, "description",
                 std::string_view("vertex-cell connectivity 0..n-1 of the n-point grids of the "
                                  "XDMF sidecar, one dataset cells/n<n> per particle count"));
    h5::Handle g = h5::create_group(f, "cells");
    std::vector<std::int64_t> ids;
    for (std::size_t n : counts) {
      ids.resize(n);
      std::iota(ids.begin(), ids.end(), std::int64_t{0});
      h5::write_ints(g.get(), fmt::format("n{}", n), ids, {.compress = true, .single = false});
    }
    g.reset();
  });
  cells_written_ = std::move(counts);
}

void XdmfSeries::write() {
  write_cells();
  write_text_atomically(xmf_, xdmf_document(entries_, cells_path().filename().string()));
}

}  // namespace shatter::io
