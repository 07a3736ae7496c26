#pragma once
// Naming, units and selection of particle columns for output (snapshots, XDMF, checkpoints).

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

// A set of columns to write, real and integer, in the order given.
struct ColumnSelection {
  std::vector<Field> fields;
  std::vector<IField> ifields;

  bool empty() const { return fields.empty() && ifields.empty(); }
  std::vector<std::string> names() const;
};

// Every column the store has registered, in enum order.
ColumnSelection all_columns(const ParticleStore& store);

// Resolves column names ("x", "damage", "id", ...). Throws std::invalid_argument naming the
// unknown column and the closest known name.
ColumnSelection select_columns(const std::vector<std::string>& names);

// The subset of `wanted` that `store` has registered.
ColumnSelection registered_subset(const ColumnSelection& wanted, const ParticleStore& store);

}  // namespace shatter::io
