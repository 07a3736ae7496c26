#pragma once
// Crush curves of the two compaction models (issue 29): distension alpha = rho_s / rho (the
// solid-matrix density over the bulk density) as a function of volumetric strain (eps-alpha) or
// of bulk pressure (P-alpha). Templates over T = double or a SIMD batch (constitutive/simd.hpp);
// branch-free, every regime evaluated and selected per lane. The policy that carries alpha per
// point is kernels/porosity/porosity.hpp; the CLI (`shatter material NAME`) and the tests
// evaluate these same functions.

#include "constitutive/simd.hpp"

namespace shatter::porosity {

// eps-alpha (Wuennemann, Collins & Melosh 2006, Icarus 180, 514, "W06"), parameters as W06
// Sec. 2 names them. Volumetric strain eps_V is negative in compression.
struct EpsAlphaParams {
  double alpha0 = 1.0;  // initial distension (>= 1)
  double eps_e = 0.0;   // elastic volumetric strain threshold (<= 0)
  double kappa = 1.0;   // exponential compaction rate, 0 < kappa <= 1
  double chi = 1.0;     // c_e / c_s: porous over solid elastic sound speed at alpha0 (CMW11)
  double eps_x = 0.0;   // exponential -> power-law transition (<= eps_e)

  // W06 Eq. 9: alpha_x = alpha0 exp(kappa (eps_x - eps_e)).
  double alpha_x() const;
  // W06 Eq. 10: the strain of full compaction, eps_c = 2 (1 - alpha_x) / (kappa alpha_x) + eps_x,
  // chosen so that Eq. 9's power law meets the exponential with the same slope at eps_x.
  double eps_c() const;
};

// P-alpha (Herrmann 1969, J. Appl. Phys. 40, 2490; Carroll & Holt 1972, J. Appl. Phys. 43,
// 1626), in the form of Jutzi, Benz & Michel 2008 (Icarus 198, 242, "JBM08") Eq. 8 with a
// general exponent (n = 2 is JBM08's quadratic).
struct PAlphaParams {
  double alpha0 = 1.0;  // initial (= elastic) distension alpha_e
  double p_e = 0.0;     // pressure at which plastic compaction starts, Pa
  double p_s = 0.0;     // pressure of full compaction (alpha = 1), Pa (> p_e)
  double n = 2.0;       // exponent of the crush curve
  double c_e = 0.0;     // elastic sound speed of the porous material, m/s (0: the solid's)
  // The two-stage ("steep") crush curve of Jutzi et al. 2009 (Icarus 201, 802, "JBM09"; fitted
  // to pumice): a steep term that closes alpha0 - alpha_t of the distension between p_e and the
  // transition pressure p_t, and a slow term that closes the remaining alpha_t - 1 between p_e and
  // p_s. p_t = 0 keeps the single-stage curve above.
  double p_t = 0.0;      // transition pressure, Pa (p_e < p_t <= p_s), 0: single stage
  double alpha_t = 1.0;  // 1 + the slow term's amplitude (1 <= alpha_t <= alpha0)
  double n2 = 2.0;       // exponent of the slow (p_e .. p_s) term; n is the steep term's
};

inline double EpsAlphaParams::alpha_x() const {
  return alpha0 * simd::vexp(kappa * (eps_x - eps_e));
}

inline double EpsAlphaParams::eps_c() const {
  const double ax = alpha_x();
  return 2.0 * (1.0 - ax) / (kappa * ax) + eps_x;
}

// W06 Eqs. 8-10: alpha(eps_V) along a monotone compression from alpha0.
//   eps >= eps_e:          alpha0                                       (elastic, Eq. 8 top)
//   eps_x <= eps < eps_e:  alpha0 exp(kappa (eps - eps_e))              (Eq. 8, exponential)
//   eps_c < eps < eps_x:   1 + (alpha_x - 1) ((eps_c - eps)/(eps_c - eps_x))^2   (Eq. 9)
//   eps <= eps_c:          1
// alpha_x and eps_c are passed in (precomputed once per material).
template <class T>
inline T eps_alpha_crush(const EpsAlphaParams& q, double alpha_x, double eps_c, const T& eps) {
  using simd::vselect;
  const T expo = q.alpha0 * simd::vexp(q.kappa * simd::vmin(eps - q.eps_e, T(0.0)));
  // (eps_c - eps) / (eps_c - eps_x) in [0, 1] on the power-law branch (both negative there);
  // clamped so the unused branch stays finite.
  const T r = simd::vmin(eps_c - eps, T(0.0)) * (1.0 / (eps_c - q.eps_x));
  const T power = 1.0 + (alpha_x - 1.0) * r * r;
  T a = vselect(eps < q.eps_x, power, expo);
  a = vselect(eps <= eps_c, T(1.0), a);
  return vselect(eps >= q.eps_e, T(q.alpha0), a);
}

// JBM08 Eq. 8: alpha(P) = 1 + (alpha_e - 1) ((p_s - P) / (p_s - p_e))^n between p_e and p_s,
// alpha_e = alpha0 below p_e, 1 above p_s. With p_t > 0 the two-stage curve of JBM09 (as
// miluphcuda's crushcurve_style 1 integrates it, src/pressure.cu, with alpha_0 = alpha_e):
//   alpha(P) = 1 + (alpha_e - alpha_t) r_t^n + (alpha_t - 1) r_s^n2,
//   r_t = (p_t - P)/(p_t - p_e) clamped to [0, 1], r_s = (p_s - P)/(p_s - p_e) clamped,
// alpha_e at p_e, 1 + (alpha_t - 1) r_s^n2 from p_t on, 1 at p_s.
// x^k for an integer k >= 1 by repeated squaring (k = 2: x * x; k = 12: four products), bit for
// bit the same in every lane as in the scalar path.
template <class T>
inline T ipow(const T& x, unsigned k) {
  T result(1.0), b = x;
  for (;;) {
    if (k & 1u) result *= b;
    k >>= 1;
    if (k == 0) return result;
    b *= b;
  }
}

// r^n on the crush curve: by products when n is a whole number up to 64 (the quadratic of JBM08,
// the 12 and 3 of JBM09's pumice fit), a general pow otherwise; n is a material constant, so the
// branch is taken once per call, never per lane.
template <class T>
inline T crush_power(const T& r, double n) {
  if (n >= 1.0 && n <= 64.0 && n == static_cast<double>(static_cast<unsigned>(n))) {
    return ipow(r, static_cast<unsigned>(n));
  }
  return simd::vpow(r, T(n));
}

template <class T>
inline T p_alpha_crush(const PAlphaParams& q, const T& p) {
  using simd::vselect;
  auto ratio = [&](double top) {
    return simd::vmin(simd::vmax((top - p) * (1.0 / (top - q.p_e)), T(0.0)), T(1.0));
  };
  auto power = [](const T& r, double n) { return crush_power(r, n); };
  const T rs = ratio(q.p_s);
  T a;
  if (q.p_t > 0.0) {  // a material constant: one branch per call, never per lane
    a = 1.0 + (q.alpha0 - q.alpha_t) * power(ratio(q.p_t), q.n) +
        (q.alpha_t - 1.0) * power(rs, q.n2);
  } else {
    a = 1.0 + (q.alpha0 - 1.0) * power(rs, q.n);
  }
  return vselect(p <= q.p_e, T(q.alpha0), a);
}

}  // namespace shatter::porosity
