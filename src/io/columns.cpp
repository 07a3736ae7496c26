#include "shatter/io/columns.hpp"

#include <stdexcept>

#include <fmt/format.h>

#include "shatter/io/suggest.hpp"

namespace shatter::io {

std::string_view unit_of(Field f) {
  switch (f) {
    case Field::x:
    case Field::y:
    case Field::z:
    case Field::size0:
      return "m";
    case Field::vx:
    case Field::vy:
    case Field::vz:
    case Field::soundspeed:
      return "m/s";
    case Field::mass:
      return "kg";
    case Field::volume0:
      return "m^3";
    case Field::rho:
      return "kg/m^3";
    case Field::energy:
    case Field::heat:
    case Field::compaction_heat:
      return "J/kg";
    case Field::sxx:
    case Field::syy:
    case Field::szz:
    case Field::sxy:
    case Field::syz:
    case Field::sxz:
    case Field::pressure:
    case Field::peak_pressure:
    case Field::sdev_xx:
    case Field::sdev_yy:
    case Field::sdev_zz:
    case Field::sdev_xy:
    case Field::sdev_yz:
    case Field::sdev_xz:
      return "Pa";
    default:
      return "1";  // strains, spins, damage, flaw counts, Weibull exponent
  }
}

std::optional<Field> field_by_name(std::string_view name) {
  for (std::size_t i = 0; i < kFieldCount; ++i) {
    if (kFieldNames[i] == name) return static_cast<Field>(i);
  }
  return std::nullopt;
}

std::optional<IField> ifield_by_name(std::string_view name) {
  for (std::size_t i = 0; i < kIFieldCount; ++i) {
    if (kIFieldNames[i] == name) return static_cast<IField>(i);
  }
  return std::nullopt;
}

std::optional<Derived> derived_by_name(std::string_view name) {
  for (std::size_t i = 0; i < kDerivedCount; ++i) {
    if (kDerivedNames[i] == name) return static_cast<Derived>(i);
  }
  return std::nullopt;
}

std::vector<double> derived_values(const ParticleStore& store, Derived d) {
  const auto alpha = store.col(source_of(d));
  std::vector<double> out(store.size());
  // the porosity phi = 1 - 1/alpha (Derived::porosity, the only one)
  for (std::size_t p = 0; p < out.size(); ++p) {
    out[p] = alpha[p] >= 1.0 ? 1.0 - 1.0 / alpha[p] : 0.0;
  }
  return out;
}

std::vector<std::string> ColumnSelection::names() const {
  std::vector<std::string> out;
  for (Field f : fields) out.emplace_back(name_of(f));
  for (IField f : ifields) out.emplace_back(name_of(f));
  for (Derived d : derived) out.emplace_back(name_of(d));
  return out;
}

ColumnSelection all_columns(const ParticleStore& store) {
  ColumnSelection s;
  for (std::size_t i = 0; i < kFieldCount; ++i) {
    if (store.has(static_cast<Field>(i))) s.fields.push_back(static_cast<Field>(i));
  }
  for (std::size_t i = 0; i < kIFieldCount; ++i) {
    if (store.has(static_cast<IField>(i))) s.ifields.push_back(static_cast<IField>(i));
  }
  for (std::size_t i = 0; i < kDerivedCount; ++i) {
    if (store.has(source_of(static_cast<Derived>(i)))) s.derived.push_back(static_cast<Derived>(i));
  }
  return s;
}

ColumnSelection select_columns(const std::vector<std::string>& names) {
  ColumnSelection s;
  for (const auto& n : names) {
    if (auto f = field_by_name(n)) {
      s.fields.push_back(*f);
    } else if (auto i = ifield_by_name(n)) {
      s.ifields.push_back(*i);
    } else if (auto d = derived_by_name(n)) {
      s.derived.push_back(*d);
    } else {
      std::vector<std::string> known(kFieldNames.begin(), kFieldNames.end());
      known.insert(known.end(), kIFieldNames.begin(), kIFieldNames.end());
      known.insert(known.end(), kDerivedNames.begin(), kDerivedNames.end());
      throw std::invalid_argument(
          fmt::format("unknown particle column '{}'{}", n, did_you_mean(n, known)));
    }
  }
  return s;
}

ColumnSelection registered_subset(const ColumnSelection& wanted, const ParticleStore& store) {
  ColumnSelection s;
  for (Field f : wanted.fields) {
    if (store.has(f)) s.fields.push_back(f);
  }
  for (IField f : wanted.ifields) {
    if (store.has(f)) s.ifields.push_back(f);
  }
  for (Derived d : wanted.derived) {
    if (store.has(source_of(d))) s.derived.push_back(d);
  }
  return s;
}

}  // namespace shatter::io
