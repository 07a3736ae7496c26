#pragma once
// The porous Hugoniot's reference (issue 29): the Rankine-Hugoniot jump from porous basalt at
// rest, solved independently of the kernel (the crush curves written out from the papers), and
// the material of the planar-impact tests, shared by the MPM (porous_hugoniot_test.cpp) and SPH
// (porous_hugoniot_sph_test.cpp) runs. The jump:
//   mass:     rho00 U = rho1 (U - up)
//   momentum: P1 = rho00 U up
//   energy:   E1 = P1 (1/rho00 - 1/rho1) / 2 = up^2 / 2
//   state:    P1 = P_s(alpha1 rho1, E1) / alpha1, alpha1 = alpha(eps1), eps1 = ln(rho00 / rho1)
//             (eps-alpha), or alpha1 = alpha(P1) (P-alpha)

#include <cmath>

#include "eos/tillotson.hpp"
#include "shatter/material/catalogue.hpp"

namespace shatter::test {

inline const eos::TillotsonParams kBasalt{2700.0, 26.7e9, 26.7e9, 0.5, 1.5, 487e6,
                                          4.72e6, 18.2e6, 2000.0, 5.0, 5.0};
constexpr double kEpsE = -1e-5, kKappa = 0.98, kEpsX = -0.1;

// W06 Eqs. 8-10.
inline double w06_alpha(double a0, double eps) {
  const double ax = a0 * std::exp(kKappa * (kEpsX - kEpsE));
  const double ec = 2.0 * (1.0 - ax) / (kKappa * ax) + kEpsX;
  if (eps >= kEpsE) return a0;
  if (eps >= kEpsX) return a0 * std::exp(kKappa * (eps - kEpsE));
  if (eps > ec) return 1.0 + (ax - 1.0) * std::pow((ec - eps) / (ec - kEpsX), 2.0);
  return 1.0;
}

// JBM08 Eq. 8 (quadratic) with p_e = 1 MPa, p_s = 5 GPa: partly compacted at up = 500 m/s.
constexpr double kPe = 1e6, kPs = 5e9;
inline double jbm08_alpha(double a0, double p) {
  if (p <= kPe) return a0;
  if (p >= kPs) return 1.0;
  return 1.0 + (a0 - 1.0) * std::pow((kPs - p) / (kPs - kPe), 2.0);
}

// JBM09's two-stage crush curve (Jutzi et al. 2009, Icarus 201, 802, fitted to pumice), written
// from the form miluphcuda's documentation gives (doc/miluphcuda_documentation.tex, "Porosity
// usage"; crushcurve_style 1), independently of kernels/porosity/crush.hpp:
//   p <= p_e:        alpha_e
//   p_e < p < p_t:   1 + (alpha_e - alpha_t) ((p_t - p)/(p_t - p_e))^n1
//                      + (alpha_t - 1) ((p_s - p)/(p_s - p_e))^n2
//   p_t <= p < p_s:  1 + (alpha_t - 1) ((p_s - p)/(p_s - p_e))^n2
//   p >= p_s:        1
// With the pumice fit of data/materials.toml: p_e = 1 MPa, p_t = 68 MPa, p_s = 213 MPa, alpha_e =
// 4.64, alpha_t = 1.90, n1 = 12, n2 = 3. `second_stage = false` drops the slow term (a curve that
// is fully compacted at p_t): the test's sensitivity check.
struct TwoStage {
  double a_e = 4.64, a_t = 1.90, p_e = 1.0e6, p_t = 6.8e7, p_s = 2.13e8, n1 = 12.0, n2 = 3.0;
  bool second_stage = true;
  double operator()(double p) const {
    if (p <= p_e) return a_e;
    const double slow =
        second_stage && p < p_s ? (a_t - 1.0) * std::pow((p_s - p) / (p_s - p_e), n2) : 0.0;
    const double a1 = second_stage ? a_t : 1.0;  // the steep stage's end
    if (p < p_t) return 1.0 + (a_e - a1) * std::pow((p_t - p) / (p_t - p_e), n1) + slow;
    return 1.0 + slow;
  }
};

// The P-alpha distension at (rho, E): the root of a = crush(P_s(a rho, E) / a) on [1, a0] by
// bisection (h(1) <= 0 < h(a0) when compacting).
template <class Crush>
double p_alpha_state(const Crush& crush, double a0, double rho, double e) {
  const eos::Tillotson eos(kBasalt);
  auto h = [&](double a) { return a - crush(eos.evaluate<double>(a * rho, e).p / a); };
  if (!(h(a0) > 0.0)) return a0;
  double lo = 1.0, hi = a0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (h(mid) > 0.0 ? hi : lo) = mid;
  }
  return lo;
}

// The distension of the porous state at (rho, E): W06 from the strain, JBM08 from the pressure.
inline double model_alpha(bool p_alpha, double a0, double rho, double e) {
  const double rho00 = kBasalt.rho0 / a0;
  if (!p_alpha) return w06_alpha(a0, std::log(rho00 / rho));
  return p_alpha_state([a0](double p) { return jbm08_alpha(a0, p); }, a0, rho, e);
}

struct Jump {
  double rho, p, us, alpha;
};

// The jump at particle speed up into porous material at rest (rho00, E = 0, P = 0), the
// distension of the shocked state given by alpha_of(rho1, E1): bisection on rho1 of
// P_model(rho1, up^2/2) - rho00 up^2 rho1 / (rho1 - rho00).
template <class AlphaOf>
Jump porous_jump_with(const AlphaOf& alpha_of, double a0, double up) {
  const eos::Tillotson eos(kBasalt);
  const double rho00 = kBasalt.rho0 / a0, e1 = 0.5 * up * up;
  auto residual = [&](double rho1) {
    const double a = alpha_of(rho1, e1);
    return eos.evaluate<double>(a * rho1, e1).p / a - rho00 * up * up * rho1 / (rho1 - rho00);
  };
  double lo = rho00 * (1.0 + 1e-9), hi = 1.5 * kBasalt.rho0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (residual(mid) > 0.0 ? hi : lo) = mid;
  }
  const double rho1 = 0.5 * (lo + hi), us = up * rho1 / (rho1 - rho00);
  return {rho1, rho00 * us * up, us, alpha_of(rho1, e1)};
}

inline Jump porous_jump(bool p_alpha, double a0, double up) {
  return porous_jump_with([&](double rho, double e) { return model_alpha(p_alpha, a0, rho, e); },
                          a0, up);
}

// The jump into pumice (the two-stage curve above on the Tillotson basalt matrix, as the catalogue
// entry `pumice`), from rest at alpha0 = alpha_e.
inline Jump pumice_jump(double up, const TwoStage& curve = {}) {
  return porous_jump_with(
      [&](double rho, double e) { return p_alpha_state(curve, curve.a_e, rho, e); }, curve.a_e, up);
}

inline MaterialSpec porous_basalt(bool p_alpha, double a0) {
  MaterialSpec s;
  s.name = "porous";
  s.source = "test";
  s.eos = "tillotson";
  s.strength = "hydro";
  s.porosity = p_alpha ? "p_alpha" : "eps_alpha";
  s.params = {{"rho0", 2700.0},   {"A", 26.7e9},  {"B", 26.7e9},   {"a", 0.5},
              {"b", 1.5},         {"E0", 487e6},  {"Eiv", 4.72e6}, {"Ecv", 18.2e6},
              {"rho_iv", 2000.0}, {"alpha", 5.0}, {"beta", 5.0},   {"alpha0", a0}};
  if (p_alpha) {
    s.params.insert({{"p_e", kPe}, {"p_s", kPs}});
  } else {
    s.params.insert({{"eps_e", kEpsE}, {"kappa", kKappa}, {"eps_x", kEpsX}, {"chi", 1.0}});
  }
  return s;
}

}  // namespace shatter::test
