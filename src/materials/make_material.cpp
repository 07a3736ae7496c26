// make_material (catalogue.hpp): parameter set + damage spec -> composed constitutive model.

#include <variant>

#include "materials/composed_model.hpp"
#include "materials/damage_factory.hpp"
#include "materials/model_factory.hpp"
#include "materials/porosity_factory.hpp"
#include "shatter/material/catalogue.hpp"

namespace shatter {

MaterialPtr make_material(const MaterialSpec& spec, const DamageSpec& damage) {
  validate(spec);
  const materials::AnyStrength s = materials::make_strength(spec);
  const double young = std::visit([](const auto& m) { return m.elastic.young; }, s);
  const materials::AnyDamage d = materials::make_damage(damage, young);
  const auto coupling = materials::damage_coupling(damage);
  if (!spec.porosity.empty()) {
    // The porosity stage composed in (kernels/porosity/porosity.hpp, issue 29).
    const porosity::Porous por = materials::make_porosity(spec);
    return std::visit(
        [&](const auto& e) { return materials::compose_porous(e, s, d, coupling, por, spec.name); },
        materials::make_eos(spec));
  }
  return std::visit([&](const auto& e) { return materials::compose(e, s, d, coupling, spec.name); },
                    materials::make_eos(spec));
}

}  // namespace shatter
