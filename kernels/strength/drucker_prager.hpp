#pragma once
// Drucker–Prager with tension cut-off and non-associated flow (MPM paper App. B.3):
//   shear surface   f_s = tau - q_phi p - Y0      (Eq. 44), tau = sqrt(J2)
//   tension surface f_t = p_t - p                 (Eq. 45), p_t <= 0
//   plastic potential psi = tau - q_psi p         (Eq. 46)
// Shear return (exact, the surface is linear): from Eq. 39 with r = s/(2 tau) + q_psi I/3,
//   dlambda = f_s* / (G + K q_phi q_psi),  p = p* + K q_psi dlambda,  tau = tau* - G dlambda.
// Tension: p = p_t, and the deviator is capped at the shear strength at the cut-off,
// tau <= q_phi p_t + Y0 (the corner of the truncated cone). Validation guarantees
// q_phi p_t + Y0 >= 0, so the corner lies on the shear surface.

#include "strength/strength_common.hpp"

namespace shatter::strength {

struct DruckerPrager {
  static constexpr FieldSet kFields{Field::plastic_strain, Field::heat};
  static constexpr bool kHasShear = true;
  ElasticConstants elastic{};
  double cohesion = 0.0;        // Y0 (Pa)
  double friction = 0.0;        // q_phi
  double dilatancy = 0.0;       // q_psi
  double tension_cutoff = 0.0;  // p_t (Pa, <= 0)

  template <class T>
  T yield(const T& p) const {
    return friction * p + cohesion;
  }

  template <class T>
  void return_map(T (&s)[6], PlasticState<T>& st) const {
    const T G = elastic.G * st.modulus;  // the point's moduli (PlasticState::modulus)
    const T K = elastic.K * st.modulus;
    const T p_trial = st.p;
    const T tau_trial = vsqrt(j2(s));

    // Shear branch.
    const T fs = tau_trial - yield(p_trial);
    const T dl = vmax(fs, T(0.0)) / (G + K * friction * dilatancy);
    const T p_shear = p_trial + K * dilatancy * dl;
    const T tau_shear = tau_trial - G * dl;
    // Tension branch: cut-off pressure and corner strength, only where the shear return would
    // end below p_t. Choosing it by p* < p_t alone jumped at p* = p_t: the dilatant shear return
    // from just below p_t ends at p > p_t, admissible, and meets the corner where p_shear = p_t.
    const auto tension = p_shear < tension_cutoff;
    const T tau_corner = vmin(tau_trial, T(friction * tension_cutoff + cohesion));

    const T p = vselect(tension, T(tension_cutoff), p_shear);
    const T tau = vselect(tension, tau_corner, tau_shear);
    scale(s, tau / vmax(tau_trial, T(kTinyStress)));
    st.p = p;
    book_plastic_work(tau_trial, tau, p_trial, p, elastic, st);
  }
};

}  // namespace shatter::strength
