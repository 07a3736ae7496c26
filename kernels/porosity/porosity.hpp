#pragma once
// The porosity stage of the composed constitutive kernel (issue 29; composed_kernel.hpp step 3):
// a policy that turns the solid-matrix EOS into the EOS of the porous bulk and evolves the
// distension alpha = rho_s / rho (Field::distension) of each point.
//
//   NoPorosity: the EOS as it is; no column, no cost (compile-time composition).
//   Porous:     the matrix EOS at rho_s = alpha rho and the bulk pressure p = p_s(alpha rho, E) /
//               alpha (Carroll & Holt 1972 Eq. 5; W06 Eq. 3; JBM08 Eq. 5), with alpha from one of
//               the two crush curves of kernels/porosity/crush.hpp:
//     eps_alpha: alpha(eps_V) of W06 Eqs. 8-10, eps_V = ln(rho_00 / rho) the volumetric strain
//                from the initial bulk density rho_00 = rho_s0 / alpha0 (a state function of the
//                point's density, so no strain column is needed), with the elastic regime of
//                Collins, Melosh & Wuennemann 2011 (IJIE 38, 434, "CMW11") Eq. 6:
//                d alpha / d eps_V = alpha (1 - (c_e/c_s)^2) for eps_e < eps_V < 0, and c_e/c_s
//                interpolated linearly in alpha from chi (at alpha0) to 1 (at alpha = 1).
//     p_alpha:   alpha(P) of JBM08 Eq. 8 at the bulk pressure P = p_s(alpha rho, E) / alpha,
//                solved for alpha by the ITP bracketing method (the crush curve and the EOS are
//                coupled through P); sound speed JBM08 Eq. 9: c = c_s + (alpha - 1)/(alpha0 - 1)
//                (c_e - c_s).
// Compaction is irreversible: alpha never exceeds the value it had (alpha_new = min(alpha_old,
// crush)), except in eps-alpha's reversible elastic regime. Both models choose per material, at
// run time and per group (one branch per batch, no lane divergence): one policy type instead of
// two halves the kernels the porous materials add to the build.
//
// The compaction work needs no term of its own: the kernel's energy update is the p dV work of
// the bulk stress on the bulk volume change, which includes the work of closing the pores.
//
// Strength and damage of the porous bulk (issue 29), per material, each a switch (0 or 1) of the
// porosity table with the default of the model's source:
//   deviator_scaling:  the bulk deviator is the matrix's over alpha, S = S_s / alpha, as the bulk
//                      pressure is p_s / alpha: JBM08's porous stress (their SPH code's form,
//                      miluphcuda STRESS_PALPHA_POROSITY, src/internal_forces.cu, integrates
//                      d(S_s / alpha)/dt). The matrix deviator S_s is what the strength model
//                      integrates and returns to its yield surface, so the bulk carries at most
//                      Y / alpha. Default 1 for p_alpha (JBM08); 0 for eps_alpha, whose sources
//                      (W06, CMW11) scale no deviator with distension.
//   compaction_damage: crushing the pores damages the matrix (JBM08; miluphcuda
//                      src/internal_forces.cu, PALPHA_POROSITY: d(D_c^(1/3)) follows d alpha),
//                      D_c(alpha) below, added to the tensile damage in the effective stress,
//                      D = min(1, D_t + D_c) (miluphcuda src/damage.cu, damage_total). Only with a
//                      damage model. Default as deviator_scaling.
// (JBM08's equation numbers for these two are not cited: the paper was not at hand; the forms
// are read from miluphcuda's code, which implements JBM08, and the test checks our closed form
// against its rate: tests/unit/materials/porosity_degradation_test.cpp.)

#include <algorithm>
#include <cmath>

#include "constitutive/simd.hpp"
#include "eos/eos_common.hpp"
#include "porosity/crush.hpp"
#include "shatter/core/fields.hpp"

namespace shatter::porosity {

struct NoPorosity {
  static constexpr bool kEnabled = false;
  static constexpr FieldSet kFields{};
  double alpha0() const { return 1.0; }
};

enum class Model { eps_alpha, p_alpha };

class Porous {
 public:
  static constexpr bool kEnabled = true;
  static constexpr FieldSet kFields{Field::distension, Field::compaction_heat};
  // The P-alpha solve (compact_p) stops when the bracket of the root is narrower than kTolerance
  // in alpha (the 40 bisections it replaced left (alpha0 - 1) 2^-40: 4.5e-13 at alpha0 = 1.5,
  // 3.3e-12 for pumice's 4.64).
  static constexpr double kTolerance = 1e-12;

  // rho_s0: the reference density of the matrix EOS.
  static Porous eps_alpha(const EpsAlphaParams& q, double rho_s0) {
    Porous m(Model::eps_alpha, q.alpha0);
    m.ea_ = q;
    m.alpha_x_ = q.alpha_x();
    m.eps_c_ = q.eps_c();
    m.rho00_ = rho_s0 / q.alpha0;
    return m;
  }
  static Porous p_alpha(const PAlphaParams& q) {
    Porous m(Model::p_alpha, q.alpha0);
    m.pa_ = q;
    // ITP's constants (compact_p) for the widest bracket, [1, alpha0]: n_max = n_1/2 + n0 steps
    // with n_1/2 = ceil(log2((alpha0 - 1) / kTolerance)) (bisection's count) and n0 = 1;
    // kappa1 = 0.2 / (alpha0 - 1), the value Oliveira & Takahashi recommend.
    const double w0 = std::max(q.alpha0 - 1.0, kTolerance);
    m.itp_steps_ = static_cast<int>(std::ceil(std::log2(w0 / kTolerance))) + 1;
    m.itp_scale_ = 0.5 * kTolerance * std::ldexp(1.0, m.itp_steps_);
    m.itp_kappa1_ = 0.2 / w0;
    return m;
  }

  // The strength and damage switches above (validated by the material library).
  void set_degradation(bool deviator_scaling, bool compaction_damage) {
    deviator_scaling_ = deviator_scaling;
    compaction_damage_ = compaction_damage;
  }
  bool deviator_scaling() const { return deviator_scaling_; }
  bool compaction_damage() const { return compaction_damage_; }

  // The factor on the matrix deviator in the bulk stress: 1 / alpha (JBM08), or 1.
  template <class T>
  T deviator_factor(const T& alpha) const {
    return deviator_scaling_ ? T(1.0) / alpha : T(1.0);
  }

  // Compaction damage at distension alpha (0 when off). JBM08's damage of compaction in the
  // integrated form of miluphcuda's rate (src/internal_forces.cu): with r = (alpha0 - alpha) /
  // (alpha0 - 1) the compacted fraction and delta = 0.01 (its `deld`, which keeps the rate of
  // D^(1/3) finite at r = 0),
  //   D_c^(1/3) = ((r + delta)^(1/3) - delta^(1/3)) / ((1 + delta)^(1/3) - delta^(1/3)),
  // 0 before compaction (alpha = alpha0) and 1 when the pores are closed (alpha = 1).
  template <class T>
  T compaction_damage(const T& alpha) const {
    if (!compaction_damage_ || !(alpha0_ > 1.0)) return T(0.0);
    const T r = simd::vmin(simd::vmax((alpha0_ - alpha) * inv_alpha0_m1_, T(0.0)), T(1.0));
    const T d = (cbrt(r + kDamageDelta) - cbrt(T(kDamageDelta))) /
                (cbrt(T(1.0 + kDamageDelta)) - cbrt(T(kDamageDelta)));
    return d * d * d;
  }
  static constexpr double kDamageDelta = 0.01;

  // The compaction work per unit mass of one step (J/kg, > 0 when pores close), booked in the
  // compaction_heat column. The bulk specific volume is v = alpha v_s (alpha = rho_s / rho, the
  // definition of distension: Carroll & Holt 1972; W06 Sec. 2), so the bulk p dV work splits as
  //   -p dv = -p alpha dv_s  -  p v_s d alpha
  // into the matrix's work and the work of closing the pores, -p v_s d alpha = -p d alpha /
  // (alpha rho): the compaction work (the "p dV" of the pore volume v_s (alpha - 1)). Over a
  // step, trapezoidal in p and in v_s = 1 / (alpha rho) between the step's ends, as the
  // kernel's energy update integrates the bulk work; p is the mean stress the energy update
  // integrates (the composed kernel passes it with the artificial viscosity: in a shock the
  // pores close inside the viscous ramp, and the Rayleigh-line work done there is the
  // compaction heating of the shock). In eps-alpha's reversible elastic regime alpha may grow
  // back and the work is returned (negative).
  template <class T>
  T compaction_work(const T& p_old, const T& p_new, const T& a_old, const T& a_new,
                    const T& rho_old, const T& rho_new) const {
    const T vs = 0.5 * (1.0 / (a_old * rho_old) + 1.0 / (a_new * rho_new));
    return 0.5 * (p_old + p_new) * (a_old - a_new) * vs;
  }

  Model model() const { return model_; }
  double alpha0() const { return alpha0_; }
  const EpsAlphaParams& eps_params() const { return ea_; }
  const PAlphaParams& p_params() const { return pa_; }

  // The crush curve of eps-alpha at volumetric strain eps (W06 Eqs. 8-10).
  template <class T>
  T crush_eps(const T& eps) const {
    return eps_alpha_crush(ea_, alpha_x_, eps_c_, eps);
  }

  // The bulk EOS point at distension alpha: p = p_s(alpha rho, E) / alpha and c^2 of the
  // model's porous sound speed. At alpha = 1 both are the matrix EOS's values bit for bit.
  template <class Eos, class T>
  eos::EosPoint<T> bulk(const Eos& eos, const T& rho, const T& e, const T& alpha) const {
    const auto s = eos.evaluate(alpha * rho, e);
    const T frac = (alpha - 1.0) * inv_alpha0_m1_;  // 1 at alpha0, 0 when fully compacted
    T c2 = s.c2;
    if (model_ == Model::eps_alpha) {
      const T r = 1.0 + frac * (ea_.chi - 1.0);  // c_e / c_s (CMW11 Sec. 2.1)
      c2 = s.c2 * r * r;
    } else if (pa_.c_e > 0.0) {
      const T cs = simd::vsqrt(s.c2);
      const T c = cs + frac * (pa_.c_e - cs);  // JBM08 Eq. 9
      c2 = c * c;
    }
    return {s.p / alpha, simd::vselect(alpha > 1.0, c2, s.c2)};
  }

  // The distension at the end of a step from rho_old to rho at energy e (irreversible).
  template <class Eos, class T>
  T compact(const Eos& eos, const T& rho, const T& rho_old, const T& e, const T& alpha_old) const {
    if (model_ == Model::eps_alpha) return compact_eps(rho, rho_old, alpha_old);
    return compact_p(eos, rho, e, alpha_old);
  }

 private:
  Porous(Model m, double alpha0)
      : model_(m), alpha0_(alpha0), inv_alpha0_m1_(alpha0 > 1.0 ? 1.0 / (alpha0 - 1.0) : 0.0) {}

  template <class T>
  T compact_eps(const T& rho, const T& rho_old, const T& alpha_old) const {
    const T eps = simd::vlog(rho00_ / rho);  // eps_V = ln(V / V_00), < 0 in compression
    T a = alpha_old;
    if (ea_.chi != 1.0) {
      // CMW11 Eq. 6 over the step, exact for alpha's factor held at its start value.
      const T eps_old = simd::vlog(rho00_ / rho_old);
      const T r = 1.0 + (alpha_old - 1.0) * inv_alpha0_m1_ * (ea_.chi - 1.0);
      const T el = alpha_old * simd::vexp((1.0 - r * r) * (eps - eps_old));
      const auto elastic = (eps > ea_.eps_e) && (eps < 0.0);
      a = simd::vselect(elastic, simd::vmin(el, T(alpha0_)), a);
    }
    return simd::vmax(simd::vmin(a, crush_eps(eps)), T(1.0));
  }

  // JBM08: alpha = min(alpha_old, alpha(P(alpha))). h(a) = a - crush(p_s(a rho, e) / a) is <= 0
  // at a = 1 (the crush curve is >= 1) and > 0 at alpha_old where compaction is due; the root
  // between is bracketed, [lo, hi] with h(lo) <= 0 < h(hi), and found by the ITP method
  // (Oliveira & Takahashi 2021, ACM TOMS 47(1) 5, Algorithm 1 with kappa2 = 2, n0 = 1): each step
  // takes the false-position point of the bracket, moves it towards the midpoint by
  // kappa1 (hi - lo)^2 (so that both ends close in, where plain false position keeps one for
  // ever), and projects it into the ball about the midpoint that still meets the bisection's
  // bound. Superlinear where h is smooth; where it is not (the crush curve's ends p_e, p_t, p_s;
  // the EOS's region boundaries; Tillotson is discontinuous at rho_iv) never more steps than
  // bisection plus one (itp_steps_). A lane stops when its bracket is narrower than kTolerance or
  // it hits h = 0, and is frozen from then on: its result does not depend on the other lanes of
  // its batch (the SIMD and scalar paths agree bit for bit). The end where h <= 0 is returned: a
  // state that satisfies alpha <= crush(P(alpha)), so a reload to the same density does not
  // compact again (over-compaction by at most kTolerance). Lanes that do not compact keep
  // alpha_old, and a batch where none does skips the solve. (Sessions 14-15 bisected 40 times:
  // the same root to round-off; docs/validation-porosity.md, "Session 16: cost of the P-alpha
  // solve".)
  template <class Eos, class T>
  T compact_p(const Eos& eos, const T& rho, const T& e, const T& alpha_old) const {
    using simd::vselect;
    auto h = [&](const T& a) { return a - p_alpha_crush(pa_, eos.evaluate(a * rho, e).p / a); };
    T hi = alpha_old, h_hi = h(hi);
    const auto need = h_hi > 0.0;
    if (!simd::any(need)) return alpha_old;
    T lo(1.0), h_lo = h(lo);
    auto done = !need || h_lo >= 0.0;  // h(1) = 0: compacted in full, alpha = 1 is the root
    double r_scale = itp_scale_;       // eps 2^(n_max - j): the projection's radius plus w/2
    for (int j = 0; j < itp_steps_ && simd::any(!done); ++j, r_scale *= 0.5) {
      const T w = hi - lo, mid = 0.5 * (lo + hi);
      const T x_f = (lo * h_hi - hi * h_lo) / (h_hi - h_lo);  // false position
      const T sigma = vselect(mid >= x_f, T(1.0), T(-1.0));
      const T delta = itp_kappa1_ * w * w;  // truncation towards the midpoint
      const T x_t = vselect(delta <= simd::vabs(mid - x_f), x_f + sigma * delta, mid);
      const T r = r_scale - 0.5 * w;  // projection onto the bisection's ball
      T x = vselect(simd::vabs(x_t - mid) <= r, x_t, mid - sigma * r);
      x = vselect((x > lo) && (x < hi), x, mid);  // round-off at the ends
      const T hx = h(x);
      const auto move_hi = (hx > 0.0) && !done;
      const auto move_lo = !(hx > 0.0) && !done;
      hi = vselect(move_hi, x, hi);
      h_hi = vselect(move_hi, hx, h_hi);
      lo = vselect(move_lo, x, lo);
      h_lo = vselect(move_lo, hx, h_lo);
      done = done || (hi - lo <= kTolerance) || (hx == 0.0);
    }
    return vselect(need, lo, alpha_old);
  }

  // x^(1/3) for x > 0
  template <class T>
  static T cbrt(const T& x) {
    return simd::vexp(simd::vlog(x) * (1.0 / 3.0));
  }

  Model model_;
  bool deviator_scaling_ = false;
  bool compaction_damage_ = false;
  double alpha0_;
  double inv_alpha0_m1_;  // 1 / (alpha0 - 1), 0 for alpha0 = 1
  EpsAlphaParams ea_{};
  double alpha_x_ = 1.0, eps_c_ = 0.0, rho00_ = 1.0;
  PAlphaParams pa_{};
  int itp_steps_ = 0;  // ITP's n_max, its radius scale eps 2^n_max and kappa1 (p_alpha above)
  double itp_scale_ = 0.0, itp_kappa1_ = 0.0;
};

}  // namespace shatter::porosity
