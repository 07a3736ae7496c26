// Porous Hugoniot with SPH (issue 29, verification, "both methods"): the planar symmetric impact
// of porosity/porous_hugoniot_test.cpp (two porous basalt slabs 0.2 m long at +-500 m/s) through
// the SPH solver (Benz & Asphaug 1995 with Monaghan's viscosity, alpha = 1, beta = 2), the slabs'
// sides slip faces (mirror particles, uniaxial strain), against the same Rankine-Hugoniot jump
// (porous_jump.hpp): the porosity stage is the material library's, used unchanged by SPH.

// GCC 12 false positive inside AVX-512 intrinsics (PR 105593), see constitutive/simd.hpp.
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ < 13
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <tuple>

#include "porous_jump.hpp"
#include "shatter/sph/solver.hpp"
#include "support/lattice.hpp"
#include "support/sanitizers.hpp"

namespace shatter {
namespace {

using test::Jump;
using test::kBasalt;
using test::porous_basalt;
using test::porous_jump;

struct Measured {
  double p, rho, alpha, front_speed, rest_speed, energy_error;
};

// As the MPM test's run_impact: spacing s (the MPM test's h / 2), a cross-section of 2 x 2
// points between slip faces; measured between 10 s from the impact plane (the wall-heating
// layer) and 10 s behind the front, the front speed between 0.4 t2 and t2.
Measured run_impact(bool p_alpha, double a0, double up, double s, const Jump& j) {
  const auto mat = make_material(porous_basalt(p_alpha, a0));
  const double rho00 = kBasalt.rho0 / a0, len = 0.2, w = 2 * s;
  ParticleStore P0;
  test::add_box(P0, 0, {-len, 0, 0}, {0.0, w, w}, s, rho00, {up, 0, 0});
  test::add_box(P0, 0, {0.0, 0, 0}, {len, w, w}, s, rho00, {-up, 0, 0});
  SolverConfig cfg;
  cfg.domain.lo = {-2 * len, 0, 0};
  cfg.domain.hi = {2 * len, w, w};
  cfg.domain.faces = {BoundaryKind::none, BoundaryKind::none, BoundaryKind::slip,
                      BoundaryKind::slip, BoundaryKind::slip, BoundaryKind::slip};
  sph::SphSolver sim(cfg, sph::SphConfig{}, std::move(P0), {mat}, 1);
  const double e0 = sim.energy().initial;

  auto front = [&] {
    double x_front = 0.0;
    const double half_rho = 0.5 * (rho00 + j.rho);
    const auto& P = sim.particles();
    for (std::size_t p = 0; p < P.size(); ++p) {
      if (P.col(Field::rho)[p] > half_rho) x_front = std::max(x_front, P.col(Field::x)[p]);
    }
    return x_front;
  };
  const double t2 = 0.09 / (j.us - up), t1 = 0.4 * t2;
  sim.advance_to(t1);
  const double x1 = front();
  sim.advance_to(t2);
  const double x2 = front();

  const auto& P = sim.particles();
  Measured m{0, 0, 0, (x2 - x1) / (t2 - t1), 0, 0};
  int n = 0;
  for (std::size_t p = 0; p < P.size(); ++p) {
    const double x = std::abs(P.col(Field::x)[p]);
    if (x > 10 * s && x < x2 - 10 * s) {
      m.p += P.col(Field::pressure)[p];
      m.rho += P.col(Field::rho)[p];
      m.alpha += P.col(Field::distension)[p];
      m.rest_speed += std::abs(P.col(Field::vx)[p]);
      ++n;
    }
  }
  EXPECT_GT(n, 100);
  m.p /= n;
  m.rho /= n;
  m.alpha /= n;
  m.rest_speed /= n;
  m.energy_error = std::abs(sim.energy().total() - e0) / e0;
  return m;
}

class PorousHugoniotSph : public ::testing::TestWithParam<std::tuple<bool, double>> {};

TEST_P(PorousHugoniotSph, CompactedStateAndShockSpeedMatchJumpConditions) {
  const auto [p_alpha, a0] = GetParam();
  if (test::kUnderSanitizers && !p_alpha) {
    // 186 s under the sanitizers (session 16's CI), 3.6 s in Release. Sanitized elsewhere: the
    // eps-alpha kernel through the MPM step (EpsAlpha/PorousHugoniot, alpha0 1.25-2) and the
    // SPH step with a porous material (PAlpha/PorousHugoniotSph below); this case's bounds are
    // a Release check (support/sanitizers.hpp).
    GTEST_SKIP() << "eps-alpha through SPH: Release only (paths sanitized by the MPM eps-alpha "
                    "and SPH P-alpha cases)";
  }
  const double up = 500.0, s = 1e-3;
  const Jump j = porous_jump(p_alpha, a0, up);
  const Measured m = run_impact(p_alpha, a0, up, s, j);
  std::printf(
      "SPH %s alpha0 = %.2f, up = %.0f m/s, spacing = %.1f mm:\n"
      "  P   %.4g Pa (jump %.4g, %+.2f%%)\n"
      "  rho %.1f kg/m^3 (jump %.1f, %+.2f%%), alpha %.4f (jump %.4f)\n"
      "  Us-up %.1f m/s (jump %.1f, %+.2f%%), |v| behind %.2f m/s, energy error %.2e\n",
      p_alpha ? "P-alpha" : "eps-alpha", a0, up, s * 1e3, m.p, j.p, 100 * (m.p / j.p - 1), m.rho,
      j.rho, 100 * (m.rho / j.rho - 1), m.alpha, j.alpha, m.front_speed, j.us - up,
      100 * (m.front_speed / (j.us - up) - 1), m.rest_speed, m.energy_error);
  // Tolerances: those of the MPM test and for its reasons (porous_hugoniot_test.cpp): pressure
  // 3%, density 1.5%, front speed 4%, distension 0.01, material behind the shock at rest within
  // 3% of up, energy 1%. Measured (docs/validation-porosity.md): eps-alpha -1.9% / +0.5% /
  // -2.5% / 0.007, P-alpha -0.6% / -0.2% / -0.4% / 0.001, energy 2e-6 (SPH conserves it to
  // round-off and the time integration; MPM's transfers lose 1e-4). SPH's shock is wider than
  // MPM's (Monaghan viscosity over 2.4 spacings), so eps-alpha's front and pressure, read on
  // the steep part of W06's curve, sit closer to the bounds than MPM's do.
  EXPECT_NEAR(m.p, j.p, 0.03 * j.p);
  EXPECT_NEAR(m.rho, j.rho, 0.015 * j.rho);
  EXPECT_NEAR(m.front_speed, j.us - up, 0.04 * (j.us - up));
  EXPECT_NEAR(m.alpha, j.alpha, 0.01);
  EXPECT_LT(m.rest_speed, 0.03 * up);
  EXPECT_LT(m.energy_error, 0.01);
}

INSTANTIATE_TEST_SUITE_P(EpsAlpha, PorousHugoniotSph,
                         ::testing::Combine(::testing::Values(false), ::testing::Values(1.5)));
INSTANTIATE_TEST_SUITE_P(PAlpha, PorousHugoniotSph,
                         ::testing::Combine(::testing::Values(true), ::testing::Values(1.5)));

}  // namespace
}  // namespace shatter
