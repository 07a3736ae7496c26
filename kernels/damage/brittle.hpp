#pragma once
// Brittle failure on the largest principal stress (MPM paper Sec. 3.3, the paragraph after the
// flaw initialisation): D = 1 once sigma_max >= sigma_0, and it stays 1.

#include "damage/damage_policy.hpp"
#include "damage/lanes.hpp"
#include "damage/principal.hpp"

namespace shatter::damage {

struct BrittleParams {
  double sigma_0 = 0.0;  // tensile failure stress in Pa (the paper runs 20, 40 and 80 MPa)
};

struct Brittle {
  static constexpr FieldSet kFields{Field::damage};
  static constexpr bool kEnabled = true;

  BrittleParams params;

  template <class T>
  T evolve(const DamageInput<T>& in, DamageState<T>& st) const {
    const T sigma_max = largest_principal(in.s);
    st.damage = simd::vselect(sigma_max >= T(params.sigma_0), T(1.0), st.damage);
    return st.damage;
  }
};

}  // namespace shatter::damage
