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

  static ElasticConstants from_young_poisson(double young, double poisson) {
    return {young, poisson, young / (2.0 * (1.0 + poisson)), young / (3.0 * (1.0 - 2.0 * poisson))};
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
  const T dev2 = dtau * dtau / (2.0 * el.G * el.G);  // deps_p' : deps_p'
  const T vol2 = dp * dp / (3.0 * el.K * el.K);      // (tr deps_p)^2 / 3
  st.deps_p = vsqrt((2.0 / 3.0) * (dev2 + vol2));
  st.eps_p = st.eps_p + st.deps_p;
  const T dq = tau * dtau / el.G - p * dp / el.K;
  st.heat = st.heat + vmax(dq, T(0.0)) / st.rho;
}

}  // namespace shatter::strength
