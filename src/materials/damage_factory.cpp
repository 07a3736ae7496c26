#include "materials/damage_factory.hpp"

#include <stdexcept>

#include <fmt/format.h>

namespace shatter::materials {

AnyDamage make_damage(const DamageSpec& spec, double young) {
  AnyDamage d = damage::make_damage_policy(spec.model, spec.params);
  if (spec.model != "none" && !(young > 0.0)) {
    throw std::invalid_argument(fmt::format(
        "damage model '{}' needs the material's Young's modulus (Eq. 18): give young and poisson, "
        "or shear_modulus and bulk_modulus",
        spec.model));
  }
  return d;
}

constitutive::DamageCoupling damage_coupling(const DamageSpec& spec) {
  using constitutive::DamageCoupling;
  if (spec.coupling.empty()) return constitutive::kDefaultCoupling;
  for (auto c : {DamageCoupling::total, DamageCoupling::incremental, DamageCoupling::lagged}) {
    if (spec.coupling == constitutive::coupling_name(c)) return c;
  }
  throw std::invalid_argument(
      fmt::format("damage: unknown value '{}' of 'coupling' (known: total, incremental, lagged)",
                  spec.coupling));
}

}  // namespace shatter::materials
