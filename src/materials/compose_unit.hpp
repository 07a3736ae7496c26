#pragma once
// What every compose_<eos>.cpp and compose_porous_<eos>.cpp starts with. Each of those files
// defines one EOS's compose()/compose_porous() overload (declared in composed_model.hpp), so the
// heavy kernel instantiations stay one translation unit per EOS and compile in parallel.

// GCC 12 false positive inside AVX-512 intrinsics (PR 105593), see constitutive/simd.hpp; it
// must be silenced before the intrinsic headers are first included, so this header comes first
// in those files and includes the kernel itself.
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ < 13
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif
#include "materials/composed_model.hpp"

// compose(const eos::EOS&, ...) defined over compose_with: the one line of compose_<eos>.cpp.
#define SHATTER_COMPOSE(EOS)                                                     \
  shatter::MaterialPtr shatter::materials::compose(                              \
      const eos::EOS& eos, const AnyStrength& strength, const AnyDamage& damage, \
      constitutive::DamageCoupling coupling, const std::string& name) {          \
    return compose_with(eos, strength, damage, coupling, name);                  \
  }

// compose_porous(const eos::EOS&, ...) over compose_porous_with: compose_porous_<eos>.cpp.
#define SHATTER_COMPOSE_POROUS(EOS)                                              \
  shatter::MaterialPtr shatter::materials::compose_porous(                       \
      const eos::EOS& eos, const AnyStrength& strength, const AnyDamage& damage, \
      constitutive::DamageCoupling coupling, const porosity::Porous& por,        \
      const std::string& name) {                                                 \
    return compose_porous_with(eos, strength, damage, coupling, por, name);      \
  }
