#include "shatter/io/xdmf.hpp"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

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

const SnapshotDataset* find(const XdmfEntry& e, std::string_view name) {
  for (const SnapshotDataset& d : e.datasets) {
    if (d.name == name) return &d;
  }
  return nullptr;
}

}  // namespace

std::string xdmf_document(const std::vector<XdmfEntry>& entries) {
  std::string doc =
      "<?xml version=\"1.0\" ?>\n"
      "<Xdmf Version=\"3.0\">\n"
      "  <Domain>\n"
      "    <Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (const XdmfEntry& e : entries) {
    doc += fmt::format("      <Grid Name=\"{}\" GridType=\"Uniform\">\n",
                       xml_escape(std::filesystem::path(e.file).stem().string()));
    doc += fmt::format("        <Time Value=\"{}\" />\n", e.time);
    doc += fmt::format(
        "        <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"{}\" "
        "NodesPerElement=\"1\" />\n",
        e.particles);
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
    for (const SnapshotDataset& d : e.datasets) {
      if (std::find(geometry.begin(), geometry.end(), d.name) != geometry.end()) continue;
      doc += fmt::format(
          "        <Attribute Name=\"{}\" AttributeType=\"{}\" Center=\"Node\">\n"
          "          <Information Name=\"units\" Value=\"{}\" />\n",
          xml_escape(d.name), d.xdmf_type, xml_escape(d.units));
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

void XdmfSeries::write() const {
  write_text_atomically(xmf_, xdmf_document(entries_));
}

}  // namespace shatter::io
