#pragma once
// Fatigue damage from accumulated plastic strain (MPM paper Sec. 3.3): D = sum(d eps_p) / eps_0,
// capped at 1. The strength model supplies the plastic strain increment of the step.

#include <xsimd/xsimd.hpp>

#include "damage/damage_policy.hpp"

namespace shatter::damage {

struct FatigueParams {
  double eps_0 = 0.0;  // accumulated plastic strain at full damage (dimensionless)
};

struct Fatigue {
  static constexpr FieldSet kFields{Field::damage};
  static constexpr bool kEnabled = true;

  FatigueParams params;

  template <class T>
  T evolve(const DamageInput<T>& in, DamageState<T>& st) const {
    // Plastic strain only accumulates; a negative increment would be a caller's sign error and
    // must not heal the material.
    const T dd = xsimd::max(in.dplastic, T(0.0)) * (1.0 / params.eps_0);
    st.damage = xsimd::min(st.damage + dd, T(1.0));
    return st.damage;
  }
};

}  // namespace shatter::damage
