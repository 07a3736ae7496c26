#pragma once
// Damage specs -> damage policies: the fracture area's factory (kernels/damage/policies.hpp),
// whose variant the composed model visits to instantiate one kernel per policy type.

#include "constitutive/composed_kernel.hpp"
#include "damage/policies.hpp"
#include "shatter/material/catalogue.hpp"

namespace shatter::materials {

using AnyDamage = damage::AnyDamage;

// Throws std::invalid_argument for an unknown model or parameter (never a silent fallback), and
// for a damage model on a material without Young's modulus (Eq. 18 needs E_Y).
AnyDamage make_damage(const DamageSpec& spec, double young);

// DamageSpec::coupling -> the kernel's damage-stress coupling (composed_kernel.hpp): "total",
// "incremental" or "lagged"; empty = constitutive::kDefaultCoupling. Anything else throws
// std::invalid_argument naming the key 'coupling' and the known values.
constitutive::DamageCoupling damage_coupling(const DamageSpec& spec);

}  // namespace shatter::materials
