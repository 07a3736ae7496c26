#include "io/particles_h5.hpp"

#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "io/h5.hpp"

namespace shatter::io {

void write_particles(hid_t file, const ParticleStore& store, const ColumnSelection& columns,
                     const std::function<void(std::string_view)>& after_column) {
  h5::Handle particles = h5::create_group(file, "particles");
  h5::set_attr(particles.get(), "count", std::uint64_t{store.size()});
  for (Field f : columns.fields) {
    const std::string name(name_of(f));
    h5::write_doubles(particles.get(), name, store.col(f));
    h5::Handle set{H5Dopen2(particles.get(), name.c_str(), H5P_DEFAULT), H5Dclose};
    h5::set_attr(set.get(), "units", unit_of(f));
    if (after_column) after_column(name);
  }
  for (IField f : columns.ifields) {
    const std::string name(name_of(f));
    h5::write_ints(particles.get(), name, store.col(f));
    h5::Handle set{H5Dopen2(particles.get(), name.c_str(), H5P_DEFAULT), H5Dclose};
    h5::set_attr(set.get(), "units", unit_of(f));
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
    if (auto f = field_by_name(name)) {
      s.fields.push_back(*f);
    } else if (auto i = ifield_by_name(name)) {
      s.ifields.push_back(*i);
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

  h5::Handle particles = h5::open_group(file, "particles");
  for (Field f : columns.fields) {
    const auto data = h5::read_doubles(particles.get(), std::string(name_of(f)), verify);
    if (data.size() != n) {
      throw std::runtime_error(fmt::format("{}: column '{}' has {} values, expected {}", where,
                                           name_of(f), data.size(), n));
    }
    std::copy(data.begin(), data.end(), store.col(f).begin());
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
