#pragma once
// Damage specs -> damage policies: the damage models by name (DamageSpec::model in
// shatter/material/catalogue.hpp), whose variant (kernels/damage/policies.hpp) the composed model
// visits to instantiate one kernel per policy type. Unknown model names and unknown parameter
// keys are errors, never silent fallbacks.
//
// Keys (SI units):
//   grady_kipp: crack_speed_factor (0.4), rs (0 = from particle volume), intact_soundspeed
//               (0 = current c_p), min_intact_fraction, and the flaw keys read by
//               shatter::flaw_spec_from_params: weibull_m, weibull_k [m^-3], total_flaws,
//               explicit_flaws (0 | 1), seed
//   brittle:    sigma_0 [Pa]            (required)
//   fatigue:    eps_0 [-]               (required)

#include <map>
#include <string>
#include <string_view>

#include "constitutive/composed_kernel.hpp"
#include "damage/policies.hpp"
#include "shatter/material/catalogue.hpp"

namespace shatter::materials {

using AnyDamage = damage::AnyDamage;

// The policy of model `model` with its parameters; std::invalid_argument for an unknown model,
// an unknown or missing parameter, or a parameter out of range.
AnyDamage make_damage_policy(std::string_view model, const std::map<std::string, double>& params);

// Throws std::invalid_argument for an unknown model or parameter (never a silent fallback), and
// for a damage model on a material without Young's modulus (Eq. 18 needs E_Y).
AnyDamage make_damage(const DamageSpec& spec, double young);

// DamageSpec::coupling -> the kernel's damage-stress coupling (composed_kernel.hpp): "total",
// "incremental" or "lagged"; empty = constitutive::kDefaultCoupling. Anything else throws
// std::invalid_argument naming the key 'coupling' and the known values.
constitutive::DamageCoupling damage_coupling(const DamageSpec& spec);

}  // namespace shatter::materials
