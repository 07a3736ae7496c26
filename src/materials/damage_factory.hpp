#pragma once
// Damage specs -> damage policies (kernels/damage).

#include <variant>

#include "damage/damage_policy.hpp"
#include "shatter/material/catalogue.hpp"

namespace shatter::materials {

using AnyDamage = std::variant<damage::NoDamage>;

// Throws std::invalid_argument for an unknown model, or one whose policy is not available.
AnyDamage make_damage(const DamageSpec& spec);

}  // namespace shatter::materials
