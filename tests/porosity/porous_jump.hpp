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

// The distension of the porous state at (rho, E): W06 from the strain; for P-alpha the root of
// a = crush(P_s(a rho, E) / a) on [1, a0] by bisection (h(1) <= 0 < h(a0) when compacting).
inline double model_alpha(bool p_alpha, double a0, double rho, double e) {
  const double rho00 = kBasalt.rho0 / a0;
  if (!p_alpha) return w06_alpha(a0, std::log(rho00 / rho));
  const eos::Tillotson eos(kBasalt);
  auto h = [&](double a) { return a - jbm08_alpha(a0, eos.evaluate<double>(a * rho, e).p / a); };
  if (!(h(a0) > 0.0)) return a0;
  double lo = 1.0, hi = a0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (h(mid) > 0.0 ? hi : lo) = mid;
  }
  return lo;
}

struct Jump {
  double rho, p, us, alpha;
};

// The jump at particle speed up into porous material at rest (rho00, E = 0, P = 0): bisection on
// rho1 of P_model(rho1, up^2/2) - rho00 up^2 rho1 / (rho1 - rho00).
inline Jump porous_jump(bool p_alpha, double a0, double up) {
  const eos::Tillotson eos(kBasalt);
  const double rho00 = kBasalt.rho0 / a0, e1 = 0.5 * up * up;
  auto residual = [&](double rho1) {
    const double a = model_alpha(p_alpha, a0, rho1, e1);
    return eos.evaluate<double>(a * rho1, e1).p / a - rho00 * up * up * rho1 / (rho1 - rho00);
  };
  double lo = rho00 * (1.0 + 1e-9), hi = 1.5 * kBasalt.rho0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (residual(mid) > 0.0 ? hi : lo) = mid;
  }
  const double rho1 = 0.5 * (lo + hi), us = up * rho1 / (rho1 - rho00);
  return {rho1, rho00 * us * up, us, model_alpha(p_alpha, a0, rho1, e1)};
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
