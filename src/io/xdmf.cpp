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

std::string data_item(const XdmfEntry& e, std::string_view column, bool real) {
  return fmt::format(
      "          <DataItem Dimensions=\"{}\" NumberType=\"{}\" Precision=\"8\" "
      "Format=\"HDF\">{}:/particles/{}</DataItem>\n",
      e.particles, real ? "Float" : "Int", xml_escape(e.file), column);
}

}  // namespace

std::string xdmf_document(const std::vector<XdmfEntry>& entries) {
  std::string doc =
      "<?xml version=\"1.0\" ?>\n"
      "<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n"
      "<Xdmf Version=\"2.0\">\n"
      "  <Domain>\n"
      "    <Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (const XdmfEntry& e : entries) {
    const auto& f = e.columns.fields;
    for (Field axis : {Field::x, Field::y, Field::z}) {
      if (std::find(f.begin(), f.end(), axis) == f.end()) {
        throw std::invalid_argument(fmt::format(
            "snapshot {} lacks column '{}' needed for XDMF geometry", e.file, name_of(axis)));
      }
    }
    doc += fmt::format("      <Grid Name=\"{}\" GridType=\"Uniform\">\n",
                       xml_escape(std::filesystem::path(e.file).stem().string()));
    doc += fmt::format("        <Time Value=\"{}\" />\n", e.time);
    doc += fmt::format(
        "        <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"{}\" "
        "NodesPerElement=\"1\" />\n",
        e.particles);
    doc += "        <Geometry GeometryType=\"X_Y_Z\">\n";
    for (std::string_view axis : {"x", "y", "z"}) doc += data_item(e, axis, true);
    doc += "        </Geometry>\n";
    auto attribute = [&](std::string_view name, std::string_view units, bool real) {
      doc += fmt::format(
          "        <Attribute Name=\"{}\" AttributeType=\"Scalar\" Center=\"Node\">\n"
          "          <Information Name=\"units\" Value=\"{}\" />\n",
          name, xml_escape(units));
      doc += data_item(e, name, real);
      doc += "        </Attribute>\n";
    };
    for (Field c : e.columns.fields) attribute(name_of(c), unit_of(c), true);
    for (IField c : e.columns.ifields) attribute(name_of(c), unit_of(c), false);
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
  e.columns = info.columns;
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
