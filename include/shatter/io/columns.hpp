#pragma once
// Naming, units and selection of particle columns for output (snapshots, XDMF, checkpoints).

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "shatter/core/fields.hpp"
#include "shatter/core/particles.hpp"

namespace shatter::io {

// SI unit of a column as written into file headers and attributes ("1" = dimensionless).
std::string_view unit_of(Field f);
constexpr std::string_view unit_of(IField) {
  return "1";
}

std::optional<Field> field_by_name(std::string_view name);
std::optional<IField> ifield_by_name(std::string_view name);

// Output columns computed from the state when they are written, not stored per point: the
// porosity 1 - 1/alpha from the distension alpha (issue 29; Carroll & Holt 1972: alpha =
// rho_s / rho, so the pore fraction of the volume is 1 - rho / rho_s), 0 where a point has no
// distension (a dense material's point, alpha unset). Written by snapshots like any column,
// skipped when a file is read back (it is recomputed, never restored).
enum class Derived : std::uint8_t { porosity, kCount };
inline constexpr std::size_t kDerivedCount = static_cast<std::size_t>(Derived::kCount);
inline constexpr std::array<std::string_view, kDerivedCount> kDerivedNames = {"porosity"};
constexpr std::string_view name_of(Derived d) {
  return kDerivedNames[static_cast<std::size_t>(d)];
}
constexpr std::string_view unit_of(Derived) {
  return "1";
}
// The stored field a derived column is computed from (the store must have it).
constexpr Field source_of(Derived) {
  return Field::distension;
}
std::optional<Derived> derived_by_name(std::string_view name);
// The column's values, one per point of the store (which has source_of(d)).
std::vector<double> derived_values(const ParticleStore& store, Derived d);

// A set of columns to write, real, integer and derived, in the order given.
struct ColumnSelection {
  std::vector<Field> fields;
  std::vector<IField> ifields;
  std::vector<Derived> derived;

  bool empty() const { return fields.empty() && ifields.empty() && derived.empty(); }
  std::vector<std::string> names() const;
};

// Every column the store has registered, in enum order, and the derived columns it can give.
ColumnSelection all_columns(const ParticleStore& store);

// Resolves column names ("x", "damage", "id", ...). Throws std::invalid_argument naming the
// unknown column and the closest known name.
ColumnSelection select_columns(const std::vector<std::string>& names);

// The subset of `wanted` that `store` has registered.
ColumnSelection registered_subset(const ColumnSelection& wanted, const ParticleStore& store);

}  // namespace shatter::io
