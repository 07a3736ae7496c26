#pragma once
// Shared pieces of the strength models (MPM paper App. B.1): elastic constants, the deviator
// invariants, the per-particle plastic state a return mapping reads and writes, and the plastic
// strain / heat of a return that moves (tau*, p*) to (tau, p).

#include "constitutive/simd.hpp"
#include "shatter/core/fields.hpp"

namespace shatter::strength {

// The SIMD primitives every return mapping uses, for T = double and T = batch alike.
using simd::vmax;
using simd::vmin;
using simd::vselect;
using simd::vsqrt;

struct ElasticConstants {
  double young = 0.0;    // E_Y, Pa
  double poisson = 0.0;  // nu
  double G = 0.0;        // shear modulus E_Y / (2 (1 + nu)) (App. B.1)
  double K = 0.0;        // bulk modulus E_Y / (3 (1 - 2 nu)) (Sec. 3.1)
  // The material key shear_from_eos (docs/materials.md, "Shear modulus from the EOS"): false,
  // G and K are the constants above everywhere; true, both follow the equation of state's bulk
  // modulus K_eos = rho c_K^2 at the fixed Poisson ratio nu, G = 3 K_eos (1 - 2 nu) / (2 (1 + nu))
  // (iSALE's POIS option, as the iSALE inputs of Raducan et al. 2019 set it). The composed kernel
  // then scales G and K by modulus_scale() per point (PlasticState::modulus).
  bool from_eos = false;

  static ElasticConstants from_young_poisson(double young, double poisson) {
    return {young, poisson, young / (2.0 * (1.0 + poisson)), young / (3.0 * (1.0 - 2.0 * poisson))};
  }

  // The factor on G and K at a point of density rho and EOS bulk sound speed squared c2: 1 for
  // constant moduli, K_eos / K = rho c2 / K when the moduli follow the EOS. Then G m =
  // 3 rho c2 (1 - 2 nu) / (2 (1 + nu)) (G / K = 3 (1 - 2 nu) / (2 (1 + nu)) for the constants
  // from (young, poisson) or (shear_modulus, bulk_modulus) alike), whatever young is.
  template <class T>
  T modulus_scale(const T& rho, const T& c2) const {
    if (!from_eos) return T(1.0);
    return rho * c2 * (1.0 / K);
  }
};

// Per-particle inputs and outputs of a return mapping. The deviator s itself is passed as T[6]
// (Voigt xx, yy, zz, xy, yz, xz).
template <class T>
struct PlasticState {
  T p;       // in: pressure p* from the EOS; out: corrected pressure (Eq. 5b), compression > 0
  T eps_p;   // accumulated equivalent plastic strain (in/out)
  T heat;    // accumulated specific plastic heat Q (J/kg, Eq. 40 per unit mass; in/out)
  T damage;  // D^n, damage at the start of the step (in)
  T rho;     // rho^{n+1} (in)
  T energy;  // specific internal energy E (in; Lundborg melt softening)
  T deps_p;  // out: equivalent plastic strain increment of this step
  // in: the factor on the elastic constants' G and K at this point (ElasticConstants::
  // modulus_scale; exactly 1 with constant moduli, so the return's arithmetic is unchanged)
  T modulus = T(1.0);
};

// J2 = s:s / 2 (App. B.2), with the off-diagonal Voigt entries counted twice.
template <class T>
inline T j2(const T (&s)[6]) {
  return 0.5 * (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]) + s[3] * s[3] + s[4] * s[4] + s[5] * s[5];
}

template <class T>
inline void scale(T (&s)[6], const T& f) {
  for (auto& c : s) c = c * f;
}

// Tiny stress (Pa) below which a deviator counts as zero: guards tau/tau* at tau* = 0.
inline constexpr double kTinyStress = 1e-300;

// Plastic strain and heat of a return with radial deviator scaling s = (tau/tau*) s* and a
// pressure change p* -> p, from sigma = sigma* - C : deps_p (Eq. 39):
//   deps_p' = (s* - s) / 2G,  tr(deps_p) = (p - p*) / K,
//   deps_bar = sqrt(2/3 deps_p : deps_p)                       (App. B.2),
//   dQ = sigma : deps_p = tau (tau* - tau) / G - p (p - p*) / K   (Eq. 40, per unit volume).
// Heat is dissipation and cannot be negative; with strong dilatancy at high pressure the
// volumetric term of Eq. 40 (work stored against the pressure, which Eq. 5b raises) can exceed
// the shear dissipation, and then no heat is produced (dQ clamped at 0).
template <class T>
inline void book_plastic_work(const T& tau_trial, const T& tau, const T& p_trial, const T& p,
                              const ElasticConstants& el, PlasticState<T>& st) {
  const T dtau = tau_trial - tau;
  const T dp = p - p_trial;
  const T G = el.G * st.modulus, K = el.K * st.modulus;  // the point's moduli
  const T dev2 = dtau * dtau / (2.0 * G * G);            // deps_p' : deps_p'
  const T vol2 = dp * dp / (3.0 * K * K);                // (tr deps_p)^2 / 3
  st.deps_p = vsqrt((2.0 / 3.0) * (dev2 + vol2));
  st.eps_p = st.eps_p + st.deps_p;
  const T dq = tau * dtau / G - p * dp / K;
  st.heat = st.heat + vmax(dq, T(0.0)) / st.rho;
}

}  // namespace shatter::strength
