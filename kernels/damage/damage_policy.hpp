#pragma once
// The contract between the constitutive kernel (kernels/strength, composed per material group)
// and a damage model (kernels/damage). A damage policy is called once per particle (or per SIMD
// batch: T is double or xsimd::batch<double>) after the intact stress has been updated, and
// returns the damage that scales it per MPM paper Eq. 14.
//
// A damage policy P provides:
//   static constexpr FieldSet kFields;   // columns it keeps (damage, eps_min, ...)
//   template <class T> T evolve(const DamageInput<T>& in, DamageState<T>& state) const;
//     -> returns D^{n+1} and updates the per-particle state it owns.

#include "shatter/core/fields.hpp"

namespace shatter::damage {

template <class T>
struct DamageInput {
  // Intact (undamaged) Cauchy stress at n+1, Voigt order xx, yy, zz, xy, yz, xz.
  T s[6];
  T young;       // Young's modulus E of the intact material (Eq. 18 strain from stress)
  T soundspeed;  // longitudinal sound speed c_p of the particle (crack speed c_g = 0.4 c_p)
  T volume;      // current particle volume m / rho (R_s of Eq. 19)
  T dplastic;    // plastic strain increment over this step (fatigue model)
  double dt;
};

template <class T>
struct DamageState {
  T damage;     // D in [0, 1]
  T eps_min;    // smallest activation threshold held by the particle
  T eps_max;    // largest activation threshold
  T n_flaws;    // number of flaws held
  T weibull_m;  // local Weibull exponent m_p
  T n_active;   // active flaws (diagnostic)
};

// No damage: the material never weakens. Costs nothing and registers no column.
struct NoDamage {
  static constexpr FieldSet kFields{};
  static constexpr bool kEnabled = false;
  template <class T>
  T evolve(const DamageInput<T>&, DamageState<T>&) const {
    return T(0.0);
  }
};

}  // namespace shatter::damage
