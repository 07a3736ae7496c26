#include "io/particles_h5.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "io/h5.hpp"

namespace shatter::io {

const std::vector<Bundle>& bundles() {
  static const std::vector<Bundle> b = {
      {"position", {Field::x, Field::y, Field::z}, "x y z", "Vector"},
      {"velocity", {Field::vx, Field::vy, Field::vz}, "x y z", "Vector"},
      // XDMF's Tensor6 order (a symmetric tensor: xx, xy, xz, yy, yz, zz), which ParaView's
      // Xdmf3 reader shows as a 6-component tensor.
      {"stress",
       {Field::sxx, Field::sxy, Field::sxz, Field::syy, Field::syz, Field::szz},
       "xx xy xz yy yz zz",
       "Tensor6"},
  };
  return b;
}

const Bundle* bundle_by_name(std::string_view name) {
  for (const Bundle& b : bundles()) {
    if (b.name == name) return &b;
  }
  return nullptr;
}

void write_particles(hid_t file, const ParticleStore& store, const ColumnSelection& columns,
                     const std::function<void(std::string_view)>& after_column,
                     const ParticleLayout& layout) {
  h5::Handle particles = h5::create_group(file, "particles");
  h5::set_attr(particles.get(), "count", std::uint64_t{store.size()});
  const auto selected = [&](Field f) {
    return std::find(columns.fields.begin(), columns.fields.end(), f) != columns.fields.end();
  };
  std::vector<Field> bundled;
  if (layout.bundle) {
    for (const Bundle& b : bundles()) {
      if (!std::all_of(b.components.begin(), b.components.end(), selected)) continue;
      const std::size_t k = b.components.size();
      std::vector<double> table(store.size() * k);
      for (std::size_t c = 0; c < k; ++c) {
        const auto col = store.col(b.components[c]);
        for (std::size_t p = 0; p < store.size(); ++p) table[p * k + c] = col[p];
      }
      const std::string name(b.name);
      h5::write_reals(particles.get(), name, table, k, layout.storage);
      h5::Handle set{H5Dopen2(particles.get(), name.c_str(), H5P_DEFAULT), H5Dclose};
      h5::set_attr(set.get(), "units", unit_of(b.components[0]));
      h5::set_attr(set.get(), "components", b.labels);
      bundled.insert(bundled.end(), b.components.begin(), b.components.end());
      if (after_column) after_column(name);
    }
  }
  for (Field f : columns.fields) {
    if (std::find(bundled.begin(), bundled.end(), f) != bundled.end()) continue;
    const std::string name(name_of(f));
    h5::write_reals(particles.get(), name, store.col(f), 1, layout.storage);
    h5::Handle set{H5Dopen2(particles.get(), name.c_str(), H5P_DEFAULT), H5Dclose};
    h5::set_attr(set.get(), "units", unit_of(f));
    if (after_column) after_column(name);
  }
  for (IField f : columns.ifields) {
    const std::string name(name_of(f));
    h5::write_ints(particles.get(), name, store.col(f), layout.storage);
    h5::Handle set{H5Dopen2(particles.get(), name.c_str(), H5P_DEFAULT), H5Dclose};
    h5::set_attr(set.get(), "units", unit_of(f));
    if (after_column) after_column(name);
  }
  for (Derived d : columns.derived) {
    const std::string name(name_of(d));
    h5::write_reals(particles.get(), name, derived_values(store, d), 1, layout.storage);
    h5::Handle set{H5Dopen2(particles.get(), name.c_str(), H5P_DEFAULT), H5Dclose};
    h5::set_attr(set.get(), "units", unit_of(d));
    if (after_column) after_column(name);
  }

  h5::Handle groups = h5::create_group(file, "groups");
  std::vector<std::int64_t> begin, end, material;
  for (const Group& g : store.groups()) {
    begin.push_back(static_cast<std::int64_t>(g.range.begin));
    end.push_back(static_cast<std::int64_t>(g.range.end));
    material.push_back(g.material);
  }
  h5::write_ints(groups.get(), "begin", begin);
  h5::write_ints(groups.get(), "end", end);
  h5::write_ints(groups.get(), "material", material);
}

std::size_t particles_in_file(hid_t file) {
  h5::Handle particles = h5::open_group(file, "particles");
  return static_cast<std::size_t>(h5::get_attr_u64(particles.get(), "count"));
}

ColumnSelection columns_in_file(hid_t file) {
  h5::Handle particles = h5::open_group(file, "particles");
  ColumnSelection s;
  for (const auto& name : h5::children(particles.get())) {
    if (const Bundle* b = bundle_by_name(name)) {
      s.fields.insert(s.fields.end(), b->components.begin(), b->components.end());
    } else if (auto f = field_by_name(name)) {
      s.fields.push_back(*f);
    } else if (auto i = ifield_by_name(name)) {
      s.ifields.push_back(*i);
    } else if (auto d = derived_by_name(name)) {
      s.derived.push_back(*d);
    } else {
      throw std::runtime_error(
          fmt::format("{}: unknown particle column '{}'", h5::file_name(file), name));
    }
  }
  return s;
}

ParticleStore read_particles(hid_t file, h5::Verify verify) {
  const std::string where = h5::file_name(file);
  const std::size_t n = particles_in_file(file);
  const ColumnSelection columns = columns_in_file(file);

  ParticleStore store;
  for (Field f : columns.fields) store.require(f);
  for (IField f : columns.ifields) store.require(f);
  h5::Handle particles = h5::open_group(file, "particles");
  const std::vector<std::string> names = h5::children(particles.get());

  h5::Handle groups = h5::open_group(file, "groups");
  const auto begin = h5::read_ints(groups.get(), "begin", verify);
  const auto end = h5::read_ints(groups.get(), "end", verify);
  const auto material = h5::read_ints(groups.get(), "material", verify);
  if (begin.size() != end.size() || begin.size() != material.size()) {
    throw std::runtime_error(fmt::format("{}: inconsistent /groups tables", where));
  }
  // Groups are appended in order, so they must tile [0, n) without gaps.
  std::size_t next = 0;
  for (std::size_t g = 0; g < begin.size(); ++g) {
    if (static_cast<std::size_t>(begin[g]) != next || end[g] < begin[g]) {
      throw std::runtime_error(
          fmt::format("{}: group {} does not follow group {}", where, g, g == 0 ? 0 : g - 1));
    }
    store.add_group(static_cast<int>(material[g]), static_cast<std::size_t>(end[g] - begin[g]));
    next = static_cast<std::size_t>(end[g]);
  }
  if (next != n) {
    throw std::runtime_error(
        fmt::format("{}: groups cover {} particles, file holds {}", where, next, n));
  }

  for (const std::string& name : names) {
    if (ifield_by_name(name) || derived_by_name(name)) continue;  // derived: not restored
    const Bundle* b = bundle_by_name(name);
    const std::size_t k = b != nullptr ? b->components.size() : 1;
    const h5::RealTable t = h5::read_reals(particles.get(), name, verify);
    if (t.rows != n || t.cols != k) {
      throw std::runtime_error(fmt::format("{}: dataset '{}' is {} x {}, expected {} x {}", where,
                                           name, t.rows, t.cols, n, k));
    }
    for (std::size_t c = 0; c < k; ++c) {
      auto col = store.col(b != nullptr ? b->components[c] : *field_by_name(name));
      for (std::size_t p = 0; p < n; ++p) col[p] = t.values[p * k + c];
    }
  }
  for (IField f : columns.ifields) {
    const auto data = h5::read_ints(particles.get(), std::string(name_of(f)), verify);
    if (data.size() != n) {
      throw std::runtime_error(fmt::format("{}: column '{}' has {} values, expected {}", where,
                                           name_of(f), data.size(), n));
    }
    std::copy(data.begin(), data.end(), store.col(f).begin());
  }
  return store;
}

}  // namespace shatter::io
