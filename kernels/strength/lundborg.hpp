#pragma once
// Lundborg (1968) pressure-dependent strength with the Collins et al. (2004) damaged branch
// (MPM paper App. B.3):
//   intact   Y_i = Y0 + mu_i p / (1 + mu_i p / (Ym - Y0))   (Eq. 47)
//   damaged  Y_d = mu_d p,  Y_d <= Y_i                       (Eq. 48)
//   Y = (1 - D) Y_i + D Y_d                                   (Eq. 49)
// times the linear melt factor (1 - E / E_melt) of Jutzi (2015). The return is the deviatoric
// scaling s -> s Y / tau* (the classic simplified return the paper contrasts with its Eq. 5);
// tau = sqrt(J2) is compared with Y.
//
// Optional tension cut-off p_t <= 0 (material key tension_cutoff; absent = off, the return
// below is then the original one, operation for operation): the pressure is clipped to
// p = max(p*, p_t), like the tension surface f_t = p_t - p of Drucker-Prager (App. B.3 Eq. 45;
// drucker_prager.hpp), and Y of Eqs. 47-49 is taken at the clipped p (the corner of the
// surface). For granular, cohesionless or fully damaged material, which cannot carry
// hydrostatic tension: iSALE sets the pressure of material that has failed in tension to zero
// (Collins, Melosh & Ivanov 2004, MAPS 39, the tensile-failure treatment of its damage model;
// recalled, the text was not at hand), and Spheral's solid hydro zeroes negative pressure in
// damaged material by default (its negativePressureInDamage switch). Without it the matrix EOS
// carries tension under a "cohesionless" Lundborg surface (docs/validation-porosity.md,
// Session 17). The corrected pressure goes to the state (PlasticState::p, which the composed
// kernel's effective stress and energy corrector use) and the return's work to the heat
// (book_plastic_work: dQ = tau (tau* - tau)/G - p (p - p*)/K, Eq. 40).

#include <limits>

#include "strength/strength_common.hpp"

namespace shatter::strength {

struct Lundborg {
  static constexpr FieldSet kFields{Field::plastic_strain, Field::heat};
  static constexpr bool kHasShear = true;
  // Eq. 49 carries the damage (the Collins et al. 2004 damaged branch), so the returned deviator
  // is already the damaged rock's; the composed kernel does not scale it by (1 - D) a second
  // time (Eq. 14; kernels/constitutive/composed_kernel.hpp).
  static constexpr bool kDamageInYield = true;
  ElasticConstants elastic{};
  double cohesion = 0.0;          // Y0 (Pa)
  double friction_intact = 0.0;   // mu_i
  double friction_damaged = 0.0;  // mu_d
  double strength_limit = 0.0;    // Ym (Pa)
  double melt_energy = 0.0;       // E_melt (J/kg); 0 = no melt softening
  // p_t (Pa, <= 0); -infinity = no cut-off (the default)
  double tension_cutoff = -std::numeric_limits<double>::infinity();

  bool has_tension_cutoff() const {
    return tension_cutoff > -std::numeric_limits<double>::infinity();
  }

  // Tensile strength of intact rock, p_t = -Y0 (Ym - Y0) / (mu_i Ym): Y_i(p_t) = 0, and below it
  // Eq. 47 would turn negative (and reach its pole at -(Ym - Y0)/mu_i).
  double intact_tension() const {
    return -cohesion * (strength_limit - cohesion) / (friction_intact * strength_limit);
  }

  template <class T>
  T melt_factor(const T& energy) const {
    if (melt_energy <= 0.0) return T(1.0);
    return vmin(vmax(1.0 - energy / melt_energy, T(0.0)), T(1.0));
  }

  template <class T>
  T yield(const T& p, const T& damage, const T& energy) const {
    const T pi = vmax(p, T(intact_tension()));
    const T yi = cohesion +
                 friction_intact * pi / (1.0 + friction_intact * pi / (strength_limit - cohesion));
    // Dry friction carries no tension, and is bounded by the intact strength (Eq. 48).
    const T yd = vmin(friction_damaged * vmax(p, T(0.0)), yi);
    return ((1.0 - damage) * yi + damage * yd) * melt_factor(energy);  // Eq. 49
  }

  template <class T>
  T yield_strength(const T& p, const T& damage, const PlasticState<T>& st) const {
    return yield(p, damage, st.energy);
  }

  template <class T>
  void return_map(T (&s)[6], PlasticState<T>& st) const {
    const T tau_trial = vsqrt(j2(s));
    if (has_tension_cutoff()) {
      const T p_trial = st.p;
      const T p = vmax(p_trial, T(tension_cutoff));  // f_t = p_t - p <= 0 (cf. Eq. 45)
      const T tau = vmin(tau_trial, yield(p, st.damage, st.energy));  // Eqs. 47-49 at p
      scale(s, tau / vmax(tau_trial, T(kTinyStress)));
      st.p = p;
      book_plastic_work(tau_trial, tau, p_trial, p, elastic, st);
      return;
    }
    const T tau = vmin(tau_trial, yield(st.p, st.damage, st.energy));
    scale(s, tau / vmax(tau_trial, T(kTinyStress)));
    book_plastic_work(tau_trial, tau, st.p, st.p, elastic, st);
  }
};

}  // namespace shatter::strength
