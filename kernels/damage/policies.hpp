#pragma once
// The damage models as one variant type: std::visit on an AnyDamage instantiates the constitutive
// kernel once per policy type, so the inner loop has no model branch. The policies are built by
// name in src/materials (materials::make_damage_policy, damage_factory.hpp).

#include <type_traits>
#include <variant>

#include "damage/brittle.hpp"
#include "damage/damage_policy.hpp"
#include "damage/fatigue.hpp"
#include "damage/grady_kipp.hpp"

namespace shatter::damage {

using AnyDamage = std::variant<NoDamage, GradyKipp, Brittle, Fatigue>;

// Columns the chosen model keeps (to register before particles are created).
inline FieldSet damage_fields(const AnyDamage& policy) {
  return std::visit([](const auto& p) { return std::decay_t<decltype(p)>::kFields; }, policy);
}

}  // namespace shatter::damage
