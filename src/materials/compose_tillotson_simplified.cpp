// Instantiations of the composed constitutive kernel for the tillotson_simplified EOS.
#include "materials/composed_model.hpp"

namespace shatter::materials {

MaterialPtr compose(const eos::TillotsonSimplified& eos, const AnyStrength& strength,
                    const AnyDamage& damage, const std::string& name) {
  return compose_with(eos, strength, damage, name);
}

}  // namespace shatter::materials
