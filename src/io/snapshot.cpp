#include "shatter/io/snapshot.hpp"

#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "io/h5.hpp"
#include "io/particles_h5.hpp"

namespace shatter::io {
namespace {

constexpr std::string_view kFormat = "shatter snapshot";
// 2: the root attributes are sealed (h5::seal_attrs). Snapshots without format_version are
// older ones: their datasets are checksummed, their header is not.
constexpr std::uint64_t kFormatVersion = 2;
// The header attributes the seal covers; the readers use the first six.
const std::vector<std::string> kHeaderAttrs = {
    "format",        "format_version", "time",       "step",      "program_version",
    "symmetry_axis", "units",          "time_units", "checksums", "precision"};
const std::vector<std::string> kUsedAttrs(kHeaderAttrs.begin(), kHeaderAttrs.begin() + 6);

SnapshotHeader read_header(hid_t file, const std::filesystem::path& path) {
  if (!h5::has_attr(file, "format") || h5::get_attr_string(file, "format") != kFormat) {
    throw std::runtime_error(fmt::format("{} is not a shatter snapshot", path.string()));
  }
  SnapshotHeader h;
  h.checksummed = h5::verify_attrs(file, kUsedAttrs);
  if (!h.checksummed && h5::has_attr(file, "format_version")) {
    throw std::runtime_error(fmt::format(
        "{}: the snapshot's header attributes have no checksum (attributes_crc32 missing): "
        "corrupt file",
        path.string()));
  }
  h.time = h5::get_attr_double(file, "time");
  h.step = h5::get_attr_u64(file, "step");
  h.program_version = h5::get_attr_string(file, "program_version");
  h.symmetry_axis = static_cast<int>(h5::get_attr_u64(file, "symmetry_axis")) - 1;
  return h;
}

}  // namespace

void write_snapshot(const std::filesystem::path& file, const ParticleStore& store,
                    const SnapshotHeader& header, const ColumnSelection& columns,
                    const SnapshotOptions& options) {
  h5::QuietErrors quiet;
  // A failed write (a full disk) leaves no temporary file behind.
  h5::write_file_atomically(file, [&](hid_t f) {
    h5::set_attr(f, "format", kFormat);
    h5::set_attr(f, "format_version", kFormatVersion);
    h5::set_attr(f, "time", header.time);
    h5::set_attr(f, "time_units", std::string_view("s"));
    h5::set_attr(f, "step", header.step);
    h5::set_attr(f, "program_version", header.program_version);
    // Stored shifted by one so that "none" (-1) fits an unsigned attribute.
    h5::set_attr(f, "symmetry_axis", static_cast<std::uint64_t>(header.symmetry_axis + 1));
    h5::set_attr(f, "units", std::string_view("SI; see the units attribute of each column"));
    h5::set_attr(f, "checksums",
                 std::string_view("crc32 (zlib) of each dataset's values in its attribute crc32"));
    if (!options.body_names.empty() || !options.material_names.empty()) {
      h5::Handle names = h5::create_group(f, "names");
      h5::write_strings(names.get(), "body", options.body_names);
      h5::write_strings(names.get(), "material", options.material_names);
    }
    h5::set_attr(f, "precision",
                 std::string_view(options.single_precision ? "binary32" : "binary64"));
    h5::seal_attrs(f, kHeaderAttrs);
    const ParticleLayout layout{true, {true, options.single_precision}};
    write_particles(f, store, columns, {}, layout);
  });
}

Snapshot read_snapshot(const std::filesystem::path& file) {
  h5::QuietErrors quiet;
  h5::Handle f = h5::open_file(file);
  Snapshot s;
  s.header = read_header(f.get(), file);
  // A snapshot that declares checksums must carry one on every dataset; older ones have none.
  const auto verify =
      h5::has_attr(f.get(), "checksums") ? h5::Verify::required : h5::Verify::if_present;
  s.particles = read_particles(f.get(), verify);
  if (h5::exists(f.get(), "names")) {
    h5::Handle names = h5::open_group(f.get(), "names");
    s.body_names = h5::read_strings(names.get(), "body", verify);
    s.material_names = h5::read_strings(names.get(), "material", verify);
  }
  return s;
}

SnapshotInfo inspect_snapshot(const std::filesystem::path& file) {
  h5::QuietErrors quiet;
  h5::Handle f = h5::open_file(file);
  SnapshotInfo info;
  info.header = read_header(f.get(), file);
  info.particles = particles_in_file(f.get());
  info.columns = columns_in_file(f.get());
  h5::Handle particles = h5::open_group(f.get(), "particles");
  for (const std::string& name : h5::children(particles.get())) {
    const h5::DatasetShape shape = h5::dataset_shape(particles.get(), name);
    SnapshotDataset d;
    d.name = name;
    d.components = shape.cols;
    d.real = shape.real;
    d.bytes = shape.bytes;
    h5::Handle set{H5Dopen2(particles.get(), name.c_str(), H5P_DEFAULT), H5Dclose};
    if (h5::has_attr(set.get(), "units")) d.units = h5::get_attr_string(set.get(), "units");
    const Bundle* b = bundle_by_name(name);
    d.xdmf_type = b != nullptr ? std::string(b->xdmf_type) : "Scalar";
    info.datasets.push_back(std::move(d));
  }
  return info;
}

}  // namespace shatter::io
