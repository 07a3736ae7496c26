// Instantiations of the composed constitutive kernel for the linear_elastic EOS.
#include "materials/composed_model.hpp"

namespace shatter::materials {

MaterialPtr compose(const eos::LinearElastic& eos, const AnyStrength& strength,
                    const AnyDamage& damage, const std::string& name) {
  return compose_with(eos, strength, damage, name);
}

}  // namespace shatter::materials
