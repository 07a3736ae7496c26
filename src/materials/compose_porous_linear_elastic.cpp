// Instantiations of the composed constitutive kernel with the porosity stage for the linear_elastic
// EOS. GCC 12 false positive inside AVX-512 intrinsics (PR 105593), see constitutive/simd.hpp; it
// must be silenced before the intrinsic headers are first included.
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ < 13
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif
#include "materials/composed_model.hpp"

namespace shatter::materials {

MaterialPtr compose_porous(const eos::LinearElastic& eos, const AnyStrength& strength,
                           const AnyDamage& damage, constitutive::DamageCoupling coupling,
                           const porosity::Porous& por, const std::string& name) {
  return compose_porous_with(eos, strength, damage, coupling, por, name);
}

}  // namespace shatter::materials
