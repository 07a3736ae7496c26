#pragma once
// J2 flow theory by radial return (MPM paper App. B.2): von Mises perfectly plastic (Eqs. 41-42,
// plastic modulus Ep = 0) and linear isotropic hardening sigma_Y = Y + Ep eps_bar (Eq. 43).
// The return is exact for linear hardening, so no iteration is needed.

#include "strength/strength_common.hpp"

namespace shatter::strength {

struct J2Plasticity {
  static constexpr FieldSet kFields{Field::plastic_strain, Field::heat};
  static constexpr bool kHasShear = true;
  ElasticConstants elastic{};
  double yield = 0.0;            // sigma_Y at eps_bar = 0 (Pa), a von Mises (sqrt(3 J2)) stress
  double plastic_modulus = 0.0;  // Ep = d sigma_Y / d eps_bar (Pa); 0 = perfectly plastic

  template <class T>
  T yield_stress(const T& eps_p) const {
    return yield + plastic_modulus * eps_p;
  }

  // kAllWork = true makes the return in every batch (the reference of the tests; the same bits).
  template <class T, bool kAllWork = false>
  void return_map(T (&s)[6], PlasticState<T>& st) const {
    const T G = elastic.G * st.modulus;         // the point's shear modulus (PlasticState)
    const T sbar = vsqrt(3.0 * j2(s));          // sigma_bar* = sqrt(3 J2*) (Eq. 41)
    const T f = sbar - yield_stress(st.eps_p);  // Eq. 41 at the trial state
    if (!kAllWork && !simd::any(!(f <= 0.0))) {
      // Elastic in every lane: the return below would leave s and the heat as they are (a
      // ratio of exactly 1) and add a plastic increment of +0; the same bits without the
      // division. (A NaN lane takes the full path, as before.)
      st.deps_p = T(0.0);
      st.eps_p = st.eps_p + T(0.0);
      st.heat = st.heat + T(0.0);
      return;
    }
    const T deps = vmax(f, T(0.0)) / (3.0 * G + plastic_modulus);  // Eq. 43
    // s = s* (sigma_bar* - 3G deps)/sigma_bar*, equal to sigma_Y^{n+1}/sigma_bar* (Eq. 42).
    const T ratio = 1.0 - 3.0 * G * deps / vmax(sbar, T(kTinyStress));
    scale(s, ratio);
    st.deps_p = deps;
    st.eps_p = st.eps_p + deps;
    // Eq. 40: sigma : deps_p = sigma_bar^{n+1} deps_bar for J2 flow (>= 0).
    st.heat = st.heat + sbar * ratio * deps / st.rho;
  }
};

}  // namespace shatter::strength
