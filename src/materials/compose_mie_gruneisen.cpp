// Instantiations of the composed constitutive kernel for the mie_gruneisen EOS.
#include "materials/composed_model.hpp"

namespace shatter::materials {

MaterialPtr compose(const eos::MieGruneisen& eos, const AnyStrength& strength,
                    const AnyDamage& damage, const std::string& name) {
  return compose_with(eos, strength, damage, name);
}

}  // namespace shatter::materials
