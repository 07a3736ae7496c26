// Fragment tables: CSV and HDF5 (one dataset per column, units as attributes), pkdgrav-style text
// for N-body hand-off, and the cumulative mass distribution.

#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
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
  };
  return cols;
}

std::ofstream open_text(const std::filesystem::path& file) {
  std::ofstream out(file);
  if (!out) throw std::runtime_error("cannot write " + file.string());
  return out;
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
  out << '\n';
  for (const auto& f : cat.fragments) {
    out << f.id << ',' << f.particles;
    for (const auto& c : columns()) out << ',' << fmt::format("{:.17g}", c.value(f));
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

void write_fragments_pkdgrav(const FragmentCatalogue& cat, const std::filesystem::path& file) {
  auto out = open_text(file);
  out << "# shatter fragments for N-body codes (pkdgrav ss-style columns), SI units\n"
         "# id mass[kg] radius[m] x[m] y[m] z[m] vx[m/s] vy[m/s] vz[m/s] wx[rad/s] wy[rad/s] "
         "wz[rad/s]\n";
  for (const auto& f : cat.fragments) {
    out << fmt::format(
        "{} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} "
        "{:.17g}\n",
        f.id, f.mass, equal_volume_radius(f), f.centre.x(), f.centre.y(), f.centre.z(),
        f.velocity.x(), f.velocity.y(), f.velocity.z(), f.omega.x(), f.omega.y(), f.omega.z());
  }
  if (!out) throw std::runtime_error("error writing " + file.string());
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
