#pragma once
// Damage specs -> damage policies: the fracture area's factory (kernels/damage/policies.hpp),
// whose variant the composed model visits to instantiate one kernel per policy type.

#include "damage/policies.hpp"
#include "shatter/material/catalogue.hpp"

namespace shatter::materials {

using AnyDamage = damage::AnyDamage;

// Throws std::invalid_argument for an unknown model or parameter (never a silent fallback), and
// for a damage model on a material without Young's modulus (Eq. 18 needs E_Y).
AnyDamage make_damage(const DamageSpec& spec, double young);

}  // namespace shatter::materials
