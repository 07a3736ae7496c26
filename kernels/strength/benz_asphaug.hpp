#pragma once
// Benz & Asphaug (1995) von Mises limiter, their Eq. 9: S -> f S with f = min(Y0^2 / (3 J2), 1).
// Implemented as published: f scales by the square of the ratio Y0 / sigma_bar, so a yielding
// state lands inside the surface (sigma_bar = Y0^2 / sigma_bar*), not on it as the radial return
// of J2Plasticity does. Kept for comparison with the SPH reference runs.

#include "strength/strength_common.hpp"

namespace shatter::strength {

struct BenzAsphaug {
  static constexpr FieldSet kFields{Field::plastic_strain, Field::heat};
  static constexpr bool kHasShear = true;
  ElasticConstants elastic{};
  double yield = 0.0;  // Y0 (Pa)

  template <class T>
  void return_map(T (&s)[6], PlasticState<T>& st) const {
    const T three_j2 = 3.0 * j2(s);
    const T f = vmin(T(yield * yield) / vmax(three_j2, T(kTinyStress)), T(1.0));  // BA95 Eq. 9
    const T sbar = vsqrt(three_j2);
    scale(s, f);
    // tau = sqrt(J2) before and after the scaling; no pressure change.
    book_plastic_work(sbar * (1.0 / 1.7320508075688772), f * sbar * (1.0 / 1.7320508075688772),
                      st.p, st.p, elastic, st);
  }
};

}  // namespace shatter::strength
