// Fragment tables: CSV and HDF5 (one dataset per column, units as attributes; mass from each body
// and material when known), pkdgrav's binary ss format for the N-body hand-off, and the
// cumulative mass distribution.

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <hdf5.h>

#include "shatter/fracture/fragments.hpp"

namespace shatter {
namespace {

struct Column {
  const char* name;
  const char* unit;
  std::function<double(const Fragment&)> value;
};

const std::vector<Column>& columns() {
  static const std::vector<Column> cols = {
      {"mass", "kg", [](const Fragment& f) { return f.mass; }},
      {"x", "m", [](const Fragment& f) { return f.centre.x(); }},
      {"y", "m", [](const Fragment& f) { return f.centre.y(); }},
      {"z", "m", [](const Fragment& f) { return f.centre.z(); }},
      {"vx", "m/s", [](const Fragment& f) { return f.velocity.x(); }},
      {"vy", "m/s", [](const Fragment& f) { return f.velocity.y(); }},
      {"vz", "m/s", [](const Fragment& f) { return f.velocity.z(); }},
      {"px", "kg m/s", [](const Fragment& f) { return f.momentum.x(); }},
      {"py", "kg m/s", [](const Fragment& f) { return f.momentum.y(); }},
      {"pz", "kg m/s", [](const Fragment& f) { return f.momentum.z(); }},
      {"Lx", "kg m^2/s", [](const Fragment& f) { return f.angular_momentum.x(); }},
      {"Ly", "kg m^2/s", [](const Fragment& f) { return f.angular_momentum.y(); }},
      {"Lz", "kg m^2/s", [](const Fragment& f) { return f.angular_momentum.z(); }},
      {"wx", "rad/s", [](const Fragment& f) { return f.omega.x(); }},
      {"wy", "rad/s", [](const Fragment& f) { return f.omega.y(); }},
      {"wz", "rad/s", [](const Fragment& f) { return f.omega.z(); }},
      {"Jxx", "kg m^2", [](const Fragment& f) { return f.inertia(0, 0); }},
      {"Jyy", "kg m^2", [](const Fragment& f) { return f.inertia(1, 1); }},
      {"Jzz", "kg m^2", [](const Fragment& f) { return f.inertia(2, 2); }},
      {"Jxy", "kg m^2", [](const Fragment& f) { return f.inertia(0, 1); }},
      {"Jyz", "kg m^2", [](const Fragment& f) { return f.inertia(1, 2); }},
      {"Jxz", "kg m^2", [](const Fragment& f) { return f.inertia(0, 2); }},
      {"a", "m", [](const Fragment& f) { return f.axes[0]; }},
      {"b", "m", [](const Fragment& f) { return f.axes[1]; }},
      {"c", "m", [](const Fragment& f) { return f.axes[2]; }},
      {"volume", "m^3", [](const Fragment& f) { return f.volume; }},
      // The bulk density of the fragment, pores included (issue 29: a porous body's fragments
      // weigh less than their matrix); the matrix density comes with the composition.
      {"bulk_density", "kg/m^3",
       [](const Fragment& f) { return f.volume > 0.0 ? f.mass / f.volume : 0.0; }},
  };
  return cols;
}

// r-z catalogues only (issue 31): each fragment is a body of revolution; an off-axis one is a
// ring or torus whose azimuthal break-up r-z cannot resolve.
const std::vector<Column>& ring_columns() {
  static const std::vector<Column> cols = {
      {"touches_axis", "1", [](const Fragment& f) { return f.touches_axis ? 1.0 : 0.0; }},
      {"r_min", "m", [](const Fragment& f) { return f.r_min; }},
      {"r_max", "m", [](const Fragment& f) { return f.r_max; }},
  };
  return cols;
}

std::ofstream open_text(const std::filesystem::path& file) {
  std::ofstream out(file);
  if (!out) throw std::runtime_error("cannot write " + file.string());
  return out;
}

// The solid matrix's density, mass / matrix volume (the fragment's pores left out); 0 for a
// fragment without volume.
double matrix_density(const Fragment& f) {
  return f.matrix_volume > 0.0 ? f.mass / f.matrix_volume : 0.0;
}

double equal_volume_radius(const Fragment& f) {
  return std::cbrt(3.0 * f.volume / (4.0 * std::numbers::pi));
}

// Closes an HDF5 handle when it goes out of scope.
struct H5Handle {
  hid_t id;
  herr_t (*close)(hid_t);
  ~H5Handle() {
    if (id >= 0) close(id);
  }
};

void check_h5(hid_t id, const std::string& what) {
  if (id < 0) throw std::runtime_error("HDF5: " + what);
}

void write_string_attribute(hid_t target, const char* name, const std::string& value) {
  const H5Handle type{H5Tcopy(H5T_C_S1), H5Tclose};
  H5Tset_size(type.id, value.size() + 1);
  const H5Handle space{H5Screate(H5S_SCALAR), H5Sclose};
  const H5Handle attr{H5Acreate2(target, name, type.id, space.id, H5P_DEFAULT, H5P_DEFAULT),
                      H5Aclose};
  check_h5(attr.id, std::string("attribute ") + name);
  H5Awrite(attr.id, type.id, value.c_str());
}

void write_double_attribute(hid_t target, const char* name, double value) {
  const H5Handle space{H5Screate(H5S_SCALAR), H5Sclose};
  const H5Handle attr{
      H5Acreate2(target, name, H5T_NATIVE_DOUBLE, space.id, H5P_DEFAULT, H5P_DEFAULT), H5Aclose};
  check_h5(attr.id, std::string("attribute ") + name);
  H5Awrite(attr.id, H5T_NATIVE_DOUBLE, &value);
}

// Creation properties without HDF5's wall-clock modification times, so that the same fragments
// give the same bytes (a resumed run's outputs are byte-identical, docs/reliability.md).
H5Handle untimed(hid_t cls) {
  const hid_t id = H5Pcreate(cls);
  check_h5(id, "creation property list");
  H5Pset_obj_track_times(id, 0);
  return H5Handle{id, H5Pclose};  // a prvalue: no copy that would close the list twice
}

template <class V>
void write_dataset(hid_t group, const char* name, hid_t type, const std::vector<V>& data,
                   const char* unit) {
  const hsize_t dims[1] = {data.size()};
  const H5Handle space{H5Screate_simple(1, dims, nullptr), H5Sclose};
  const H5Handle dcpl = untimed(H5P_DATASET_CREATE);
  const H5Handle set{H5Dcreate2(group, name, type, space.id, H5P_DEFAULT, dcpl.id, H5P_DEFAULT),
                     H5Dclose};
  check_h5(set.id, std::string("dataset ") + name);
  if (!data.empty() && H5Dwrite(set.id, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()) < 0)
    throw std::runtime_error(std::string("HDF5: writing ") + name);
  write_string_attribute(set.id, "units", unit);
}

}  // namespace

void write_fragments_csv(const FragmentCatalogue& cat, const std::filesystem::path& file) {
  auto out = open_text(file);
  out << fmt::format("# total_mass_kg={:.17g} dust_mass_kg={:.17g} fragments={}\n", cat.total_mass,
                     cat.dust_mass, cat.fragments.size());
  out << "id,particles";
  for (const auto& c : columns()) out << ',' << c.name << '_' << c.unit;
  if (cat.axisymmetric)
    for (const auto& c : ring_columns()) out << ',' << c.name << '_' << c.unit;
  const bool composed = !cat.body_names.empty();
  if (composed) out << ",matrix_density_kg/m^3";
  for (const auto& b : cat.body_names) out << ",mass_body_" << b << "_kg";
  for (const auto& m : cat.material_names) out << ",mass_material_" << m << "_kg";
  out << '\n';
  for (const auto& f : cat.fragments) {
    out << f.id << ',' << f.particles;
    for (const auto& c : columns()) out << ',' << fmt::format("{:.17g}", c.value(f));
    if (cat.axisymmetric)
      for (const auto& c : ring_columns()) out << ',' << fmt::format("{:.17g}", c.value(f));
    if (composed) out << ',' << fmt::format("{:.17g}", matrix_density(f));
    for (double m : f.mass_by_body) out << ',' << fmt::format("{:.17g}", m);
    for (double m : f.mass_by_material) out << ',' << fmt::format("{:.17g}", m);
    out << '\n';
  }
  if (!out) throw std::runtime_error("error writing " + file.string());
}

void write_fragments_hdf5(const FragmentCatalogue& cat, const std::filesystem::path& file) {
  const H5Handle h5{H5Fcreate(file.string().c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT),
                    H5Fclose};
  check_h5(h5.id, "cannot create " + file.string());
  const H5Handle gcpl = untimed(H5P_GROUP_CREATE);
  const H5Handle group{H5Gcreate2(h5.id, "fragments", H5P_DEFAULT, gcpl.id, H5P_DEFAULT), H5Gclose};
  check_h5(group.id, "group fragments");
  write_double_attribute(group.id, "total_mass_kg", cat.total_mass);
  write_double_attribute(group.id, "dust_mass_kg", cat.dust_mass);
  std::vector<std::int64_t> ids, counts;
  for (const auto& f : cat.fragments) {
    ids.push_back(f.id);
    counts.push_back(static_cast<std::int64_t>(f.particles));
  }
  write_dataset(group.id, "id", H5T_NATIVE_INT64, ids, "1");
  write_dataset(group.id, "particles", H5T_NATIVE_INT64, counts, "1");
  std::vector<double> values(cat.fragments.size());
  for (const auto& c : columns()) {
    for (std::size_t i = 0; i < values.size(); ++i) values[i] = c.value(cat.fragments[i]);
    write_dataset(group.id, c.name, H5T_NATIVE_DOUBLE, values, c.unit);
  }
  if (cat.axisymmetric) {
    for (const auto& c : ring_columns()) {
      for (std::size_t i = 0; i < values.size(); ++i) values[i] = c.value(cat.fragments[i]);
      write_dataset(group.id, c.name, H5T_NATIVE_DOUBLE, values, c.unit);
    }
  }
  // Composition: mass_body_NAME and mass_material_NAME datasets, kg.
  auto composition = [&](const std::vector<std::string>& names, const char* kind,
                         std::vector<double> Fragment::*member) {
    for (std::size_t k = 0; k < names.size(); ++k) {
      for (std::size_t i = 0; i < values.size(); ++i) values[i] = (cat.fragments[i].*member)[k];
      write_dataset(group.id, fmt::format("mass_{}_{}", kind, names[k]).c_str(), H5T_NATIVE_DOUBLE,
                    values, "kg");
    }
  };
  if (!cat.body_names.empty()) {
    for (std::size_t i = 0; i < values.size(); ++i) values[i] = matrix_density(cat.fragments[i]);
    write_dataset(group.id, "matrix_density", H5T_NATIVE_DOUBLE, values, "kg/m^3");
  }
  composition(cat.body_names, "body", &Fragment::mass_by_body);
  composition(cat.material_names, "material", &Fragment::mass_by_material);
  const auto cumulative = cumulative_mass_distribution(cat);
  const H5Handle cgroup{H5Gcreate2(h5.id, "cumulative_mass", H5P_DEFAULT, gcpl.id, H5P_DEFAULT),
                        H5Gclose};
  check_h5(cgroup.id, "group cumulative_mass");
  std::vector<double> m, cm;
  std::vector<std::int64_t> n;
  for (const auto& c : cumulative) {
    m.push_back(c.mass);
    n.push_back(static_cast<std::int64_t>(c.count));
    cm.push_back(c.cumulative_mass);
  }
  write_dataset(cgroup.id, "mass", H5T_NATIVE_DOUBLE, m, "kg");
  write_dataset(cgroup.id, "count_ge", H5T_NATIVE_INT64, n, "1");
  write_dataset(cgroup.id, "cumulative_mass", H5T_NATIVE_DOUBLE, cm, "kg");
}

namespace {

// Each fragment's matrix volume, sum of v_p / alpha_p with v_p = m_p / rho_p (the bulk volume
// fragment_kinematics sums) and alpha_p the point's distension: rho_s = alpha rho, so the
// matrix occupies 1 / alpha of the bulk. Without a distension column every point is dense and the
// matrix volume is the fragment's volume.
void add_matrix_volume(FragmentCatalogue& cat, const ParticleStore& store) {
  if (!store.has(Field::distension)) {
    for (auto& f : cat.fragments) f.matrix_volume = f.volume;
    return;
  }
  if (!store.has(Field::rho)) {
    throw std::invalid_argument("add_composition: a distension column without a density column");
  }
  for (auto& f : cat.fragments) f.matrix_volume = 0.0;
  const auto label = store.col(IField::fragment);
  const auto mass = store.col(Field::mass);
  const auto rho = store.col(Field::rho);
  const auto alpha = store.col(Field::distension);
  for (std::size_t p = 0; p < store.size(); ++p) {
    if (label[p] < 0 || !(rho[p] > 0.0)) continue;
    // A dense material's points hold no distension (0, as the time series reads it): alpha = 1.
    const double a = alpha[p] >= 1.0 ? alpha[p] : 1.0;
    cat.fragments[static_cast<std::size_t>(label[p])].matrix_volume += mass[p] / (a * rho[p]);
  }
}

}  // namespace

void add_composition(FragmentCatalogue& cat, const ParticleStore& store,
                     const std::vector<std::string>& body_names,
                     const std::vector<std::string>& body_materials) {
  if (body_names.size() != body_materials.size()) {
    throw std::invalid_argument("add_composition: one material per body needed");
  }
  cat.body_names = body_names;
  cat.material_names.clear();
  std::vector<std::size_t> material_of;  // body -> index into material_names
  for (const auto& m : body_materials) {
    auto it = std::find(cat.material_names.begin(), cat.material_names.end(), m);
    if (it == cat.material_names.end()) it = cat.material_names.insert(it, m);
    material_of.push_back(static_cast<std::size_t>(it - cat.material_names.begin()));
  }
  for (auto& f : cat.fragments) {
    f.mass_by_body.assign(body_names.size(), 0.0);
    f.mass_by_material.assign(cat.material_names.size(), 0.0);
  }
  const auto label = store.col(IField::fragment);
  const auto body = store.col(IField::body);
  const auto mass = store.col(Field::mass);
  // Fragment ids are ranks (0 = largest), so they index cat.fragments.
  for (std::size_t p = 0; p < store.size(); ++p) {
    if (label[p] < 0) continue;
    const auto k = static_cast<std::size_t>(label[p]);
    const auto b = static_cast<std::size_t>(body[p]);
    if (k >= cat.fragments.size() || b >= body_names.size()) {
      throw std::invalid_argument(
          fmt::format("add_composition: point {} has fragment {} of {}, body {} of {}", p, label[p],
                      cat.fragments.size(), body[p], body_names.size()));
    }
    cat.fragments[k].mass_by_body[b] += mass[p];
    cat.fragments[k].mass_by_material[material_of[b]] += mass[p];
  }
  add_matrix_volume(cat, store);
}

namespace pkdgrav_units {
double time() {
  return std::sqrt(kLength * kLength * kLength / kGM);
}
}  // namespace pkdgrav_units

namespace {

// XDR: IEEE values and two's-complement ints, big-endian (RFC 4506 Secs. 4.1 and 4.6).
void put_be(std::string& out, std::uint64_t bits, int bytes) {
  for (int k = bytes - 1; k >= 0; --k) out.push_back(static_cast<char>((bits >> (8 * k)) & 0xff));
}
void put_double(std::string& out, double v) {
  put_be(out, std::bit_cast<std::uint64_t>(v), 8);
}
void put_int(std::string& out, std::int32_t v) {
  put_be(out, static_cast<std::uint32_t>(v), 4);
}
std::uint64_t get_be(const std::string& in, std::size_t& at, int bytes) {
  std::uint64_t v = 0;
  for (int k = 0; k < bytes; ++k) v = (v << 8) | static_cast<unsigned char>(in[at++]);
  return v;
}
double get_double(const std::string& in, std::size_t& at) {
  return std::bit_cast<double>(get_be(in, at, 8));
}
std::int32_t get_int(const std::string& in, std::size_t& at) {
  return static_cast<std::int32_t>(static_cast<std::uint32_t>(get_be(in, at, 4)));
}

constexpr std::size_t kSsHead = 16;  // SSHEAD_SIZE
constexpr std::size_t kSsData = 96;  // SSDATA_SIZE
constexpr std::int32_t kSsMagicStandard = -1;

}  // namespace

void write_ss(const SsFile& ss, const std::filesystem::path& file) {
  using namespace pkdgrav_units;
  const double t = time();
  if (ss.records.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max())) {
    throw std::invalid_argument(fmt::format("{}: {} records exceed the ss format's int count",
                                            file.string(), ss.records.size()));
  }
  std::string bytes;
  bytes.reserve(kSsHead + kSsData * ss.records.size());
  put_double(bytes, ss.time / t);
  put_int(bytes, static_cast<std::int32_t>(ss.records.size()));
  put_int(bytes, kSsMagicStandard);
  for (const SsRecord& r : ss.records) {
    put_double(bytes, r.mass / kMass);
    put_double(bytes, r.radius / kLength);
    for (int k = 0; k < 3; ++k) put_double(bytes, r.pos[k] / kLength);
    for (int k = 0; k < 3; ++k) put_double(bytes, r.vel[k] * t / kLength);
    for (int k = 0; k < 3; ++k) put_double(bytes, r.spin[k] * t);
    put_int(bytes, r.color);
    put_int(bytes, r.org_idx);
  }
  std::ofstream out(file, std::ios::binary);
  if (!out) throw std::runtime_error("cannot write " + file.string());
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw std::runtime_error("error writing " + file.string());
}

SsFile read_ss(const std::filesystem::path& file) {
  using namespace pkdgrav_units;
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + file.string());
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.size() < kSsHead) {
    throw std::runtime_error(
        fmt::format("{}: {} bytes, shorter than an ss header", file.string(), bytes.size()));
  }
  const double t = time();
  std::size_t at = 0;
  SsFile ss;
  ss.time = get_double(bytes, at) * t;
  const std::int32_t n = get_int(bytes, at);
  get_int(bytes, at);  // pad / magic number
  if (n < 0 || bytes.size() != kSsHead + kSsData * static_cast<std::size_t>(n)) {
    throw std::runtime_error(
        fmt::format("{}: header says {} records, file has {} bytes (expected "
                    "{} + {} per record)",
                    file.string(), n, bytes.size(), kSsHead, kSsData));
  }
  ss.records.resize(static_cast<std::size_t>(n));
  for (SsRecord& r : ss.records) {
    r.mass = get_double(bytes, at) * kMass;
    r.radius = get_double(bytes, at) * kLength;
    for (int k = 0; k < 3; ++k) r.pos[k] = get_double(bytes, at) * kLength;
    for (int k = 0; k < 3; ++k) r.vel[k] = get_double(bytes, at) * kLength / t;
    for (int k = 0; k < 3; ++k) r.spin[k] = get_double(bytes, at) / t;
    r.color = get_int(bytes, at);
    r.org_idx = get_int(bytes, at);
  }
  return ss;
}

SsFile fragments_ss(const FragmentCatalogue& cat, double time, SsRadius radius) {
  SsFile ss;
  ss.time = time;
  for (const Fragment& f : cat.fragments) {
    SsRecord r;
    r.mass = f.mass;
    r.radius = equal_volume_radius(f);
    r.pos = f.centre;
    r.vel = f.velocity;
    r.spin = f.omega;
    std::int64_t main_body = 0;
    if (!f.mass_by_body.empty()) {
      main_body =
          std::max_element(f.mass_by_body.begin(), f.mass_by_body.end()) - f.mass_by_body.begin();
    }
    r.color = ss_body_colour(main_body);
    r.org_idx = static_cast<std::int32_t>(f.id);
    ss.records.push_back(r);
  }
  if (radius == SsRadius::packing_safe) apply_packing_safe_radius(ss);
  return ss;
}

SsFile particles_ss(const ParticleStore& store, double time, SsRadius radius) {
  SsFile ss;
  ss.time = time;
  const auto m = store.col(Field::mass);
  const auto rho = store.col(Field::rho);
  const auto label = store.col(IField::fragment);
  for (std::size_t p = 0; p < store.size(); ++p) {
    SsRecord r;
    r.mass = m[p];
    r.radius = std::cbrt(3.0 * m[p] / (rho[p] * 4.0 * std::numbers::pi));
    r.pos = {store.col(Field::x)[p], store.col(Field::y)[p], store.col(Field::z)[p]};
    r.vel = {store.col(Field::vx)[p], store.col(Field::vy)[p], store.col(Field::vz)[p]};
    r.color = ss_fragment_colour(label[p]);
    r.org_idx = static_cast<std::int32_t>(p);
    ss.records.push_back(r);
  }
  if (radius == SsRadius::packing_safe) apply_packing_safe_radius(ss);
  return ss;
}

void write_cumulative_mass_csv(const FragmentCatalogue& cat, const std::filesystem::path& file) {
  auto out = open_text(file);
  out << "mass_kg,count_ge,cumulative_mass_kg,mass_over_total\n";
  for (const auto& c : cumulative_mass_distribution(cat))
    out << fmt::format("{:.17g},{},{:.17g},{:.17g}\n", c.mass, c.count, c.cumulative_mass,
                       cat.total_mass > 0.0 ? c.mass / cat.total_mass : 0.0);
  if (!out) throw std::runtime_error("error writing " + file.string());
}

}  // namespace shatter
