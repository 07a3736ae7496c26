// Porous Hugoniot (issue 29, verification): a planar symmetric impact of two porous basalt slabs
// (eps-alpha, Wuennemann et al. 2006; P-alpha, Jutzi et al. 2008) through the whole MPM step. The
// compacted state at rest between the two outgoing shocks must carry the pressure and density, and
// the shocks must run at the speed, of the Rankine-Hugoniot jump from the unshocked porous state,
// solved here independently of the kernel: W06 Eqs. 8-10 written out, the matrix Tillotson EOS, and
//   mass:     rho00 U = rho1 (U - up)
//   momentum: P1 = rho00 U up
//   energy:   E1 = P1 (1/rho00 - 1/rho1) / 2 = up^2 / 2
//   state:    P1 = P_s(alpha1 rho1, E1) / alpha1, alpha1 = alpha(eps1), eps1 = ln(rho00 / rho1)
//             (eps-alpha), or alpha1 = alpha(P1) (P-alpha)
// The total energy is checked too: the compaction work must appear as internal energy.

// GCC 12 false positive inside AVX-512 intrinsics (PR 105593), see constitutive/simd.hpp; it
// must be silenced before the intrinsic headers are first included.
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ < 13
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <tuple>

#include "eos/tillotson.hpp"
#include "porous_jump.hpp"
#include "shatter/material/catalogue.hpp"
#include "shatter/mpm/simulation.hpp"
#include "support/lattice.hpp"

namespace shatter {
namespace {

using test::Jump;
using test::kBasalt;
using test::porous_basalt;
using test::porous_jump;

struct Measured {
  double p, rho, alpha, front_speed, rest_speed, energy_error;
  double e = 0, q = 0;  // mean internal energy and booked compaction work (J/kg) in the gauge
  double e_sum = 0, q_sum = 0;  // sum m E and sum m q_c over all points (J)
};

// The symmetric impact of two slabs of `spec` (bulk density rho00), each len long; the gauges read
// when the jump's front has run `run` (from 0.4 of that time on for the front speed), between 5
// cells from the impact plane and `ramp` cells behind the front.
Measured run_impact(const MaterialSpec& spec, double rho00, double up, double h, const Jump& j,
                    double len = 0.2, double run = 0.09, double ramp = 5.0) {
  const auto mat = make_material(spec);
  ParticleStore s;
  test::add_box(s, 0, {-len, 0, 0}, {0.0, h, h}, h / 2, rho00, {up, 0, 0});
  test::add_box(s, 0, {0.0, 0, 0}, {len, h, h}, h / 2, rho00, {-up, 0, 0});
  SolverConfig cfg;
  cfg.cell_size = h;
  cfg.domain.lo = {-2 * len, 0, 0};
  cfg.domain.hi = {2 * len, h, h};
  cfg.domain.faces = {BoundaryKind::none, BoundaryKind::none, BoundaryKind::slip,
                      BoundaryKind::slip, BoundaryKind::slip, BoundaryKind::slip};
  cfg.viscosity = {0.5, 1.5};
  Simulation sim(cfg, std::move(s), {mat}, 1);
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
  // The front runs at Us - up in the frame of the compacted (resting) material: `run` by t2.
  const double t2 = run / (j.us - up), t1 = 0.4 * t2;
  sim.advance_to(t1);
  const double x1 = front();
  sim.advance_to(t2);
  const double x2 = front();

  const auto& P = sim.particles();
  Measured m{0, 0, 0, (x2 - x1) / (t2 - t1), 0, 0};
  int n = 0;
  for (std::size_t p = 0; p < P.size(); ++p) {
    const double x = std::abs(P.col(Field::x)[p]);
    if (x > 5 * h && x < x2 - ramp * h) {  // past the wall-heating layer, behind the front's ramp
      m.p += P.col(Field::pressure)[p];
      m.rho += P.col(Field::rho)[p];
      m.alpha += P.col(Field::distension)[p];
      m.rest_speed += std::abs(P.col(Field::vx)[p]);
      m.e += P.col(Field::energy)[p];
      m.q += P.col(Field::compaction_heat)[p];
      ++n;
    }
  }
  for (std::size_t p = 0; p < P.size(); ++p) {
    m.e_sum += P.col(Field::mass)[p] * P.col(Field::energy)[p];
    m.q_sum += P.col(Field::mass)[p] * P.col(Field::compaction_heat)[p];
  }
  EXPECT_GT(n, 100);
  m.p /= n;
  m.rho /= n;
  m.alpha /= n;
  m.rest_speed /= n;
  m.e /= n;
  m.q /= n;
  m.energy_error = std::abs(sim.energy().total() - e0) / e0;
  return m;
}

class PorousHugoniot : public ::testing::TestWithParam<std::tuple<bool, double>> {};

TEST_P(PorousHugoniot, CompactedStateAndShockSpeedMatchJumpConditions) {
  const auto [p_alpha, a0] = GetParam();
  const double up = 500.0, h = 2e-3;
  const Jump j = porous_jump(p_alpha, a0, up);
  const Measured m = run_impact(porous_basalt(p_alpha, a0), kBasalt.rho0 / a0, up, h, j);
  std::printf(
      "%s alpha0 = %.2f, up = %.0f m/s, h = %.0f mm:\n"
      "  P   %.4g Pa (jump %.4g, %+.2f%%)\n"
      "  rho %.1f kg/m^3 (jump %.1f, %+.2f%%), alpha %.4f (jump %.4f)\n"
      "  Us-up %.1f m/s (jump %.1f, %+.2f%%), |v| behind %.2f m/s, energy error %.2e\n",
      p_alpha ? "P-alpha" : "eps-alpha", a0, up, h * 1e3, m.p, j.p, 100 * (m.p / j.p - 1), m.rho,
      j.rho, 100 * (m.rho / j.rho - 1), m.alpha, j.alpha, m.front_speed, j.us - up,
      100 * (m.front_speed / (j.us - up) - 1), m.rest_speed, m.energy_error);
  // Tolerances (docs/validation-porosity.md): pressure 3% and density 1.5% as the solid planar
  // impact test (viscous smearing, MPM transfer noise); the density behind a compaction shock
  // sits on the steep part of the porous Hugoniot, where a 1% density error is a larger
  // pressure error, so the density bound is the tighter. Front speed from two snapshots each
  // located to ~h/2 over a 54 mm run: 2%, bound 4%. A wrong p_s / alpha, a crush curve off by
  // one regime or a missing compaction term moves these by far more (alpha0 = 1.25 -> 1.5 moves
  // P by 25%).
  EXPECT_NEAR(m.p, j.p, 0.03 * j.p);
  EXPECT_NEAR(m.rho, j.rho, 0.015 * j.rho);
  EXPECT_NEAR(m.front_speed, j.us - up, 0.04 * (j.us - up));
  // Distension behind the shock: the 1.5% density bound moves alpha by up to ~0.02 on the
  // crush curves' steepest parts here; measured within 0.002, bound 0.01.
  EXPECT_NEAR(m.alpha, j.alpha, 0.01);
  EXPECT_LT(m.rest_speed, 0.03 * up);
  // Energy: compaction work is p dV work of the bulk and stays in the budget (kinetic +
  // internal); 1% as the MPM energy checks elsewhere allow for the transfers.
  EXPECT_LT(m.energy_error, 0.01);
}

INSTANTIATE_TEST_SUITE_P(EpsAlpha, PorousHugoniot,
                         ::testing::Combine(::testing::Values(false),
                                            ::testing::Values(1.25, 1.5, 2.0)));
INSTANTIATE_TEST_SUITE_P(PAlpha, PorousHugoniot,
                         ::testing::Combine(::testing::Values(true), ::testing::Values(1.25, 1.5)));

// JBM09's two-stage crush curve through the engine: the catalogue's `pumice` (alpha0 = 4.64, bulk
// 582 kg/m^3) at up = 350 m/s, where the jump's pressure (95 MPa) lies between p_t = 68 MPa and
// p_s = 213 MPa: the state behind the shock sits on the second (slow) stage, alpha = 1.155. A
// curve without that stage (fully compacted at p_t) gives rho +15% and Us - up -17% at this up
// (porous_jump.hpp, TwoStage::second_stage): far outside the bounds below.
TEST(PorousHugoniotPumice, TwoStageCurveGivesTheJump) {
#if defined(__SANITIZE_ADDRESS__)
  // Under ASan/UBSan this run took 387 s of the CI's hour (session 15): the two-stage kernel
  // solves for alpha with 40 bisection steps of two general pow calls per point and step, ~100x
  // the dense EOS (docs/validation-porosity.md). The kernel itself runs under the sanitizers in
  // tests/unit/materials/porous_catalogue_test.cpp (the curve against its closed form); this
  // engine-level check of the same code runs in the Release tests.
  GTEST_SKIP() << "engine-level pumice Hugoniot: Release only (the two-stage kernel is checked "
                  "under the sanitizers by the PorousEntries tests)";
#endif
  const MaterialCatalogue cat = MaterialCatalogue::builtin();
  const MaterialSpec& spec = cat.get("pumice");
  const test::TwoStage curve;  // the source's numbers, not the catalogue's
  const double up = 350.0, h = 2e-3, rho00 = kBasalt.rho0 / curve.a_e;
  const Jump j = test::pumice_jump(up, curve);
  // The shock runs at Us = 4 (Us - up) in the slabs' frame: a 45 mm run consumes 0.18 m of a
  // 0.2 m slab (the 90 mm of the basalt cases would outrun it). The compaction front of this
  // steep curve is ~12 cells wide (x = 24-48 mm at t2 in a profile of the run), so the gauge
  // stops 12 cells behind the front instead of 5.
  const Measured m = run_impact(spec, rho00, up, h, j, 0.2, 0.045, 12.0);
  std::printf(
      "pumice (two-stage P-alpha), up = %.0f m/s, h = %.0f mm:\n"
      "  P   %.4g Pa (jump %.4g, %+.2f%%)\n"
      "  rho %.1f kg/m^3 (jump %.1f, %+.2f%%), alpha %.4f (jump %.4f)\n"
      "  Us-up %.1f m/s (jump %.1f, %+.2f%%), |v| behind %.2f m/s, energy error %.2e\n",
      up, h * 1e3, m.p, j.p, 100 * (m.p / j.p - 1), m.rho, j.rho, 100 * (m.rho / j.rho - 1),
      m.alpha, j.alpha, m.front_speed, j.us - up, 100 * (m.front_speed / (j.us - up) - 1),
      m.rest_speed, m.energy_error);
  // Tolerances as the basalt cases above (density 1.5%, front speed 4%, distension 0.01, rest 3%
  // of up, energy 1%), for the same reasons, except the pressure: 6%. Pumice's porous state
  // function is steep, dlnP/dlnrho = 3.1 at the jump (porous_jump.hpp), so the 1.5% density
  // bound alone allows 4.6%; and the compacted plateau sits ~0.005 below the crush curve at its
  // own pressure (the irreversible curve keeps the front's overshoot, the plateau of the
  // resolution study in docs/validation-porosity.md), which the steep second stage turns into
  // a few % of pressure (measured -4%). The pressure is not what tells the stages apart (a
  // curve without the second stage moves it only -4%); the density (+15%), distension (-0.15)
  // and front speed (-17%) are, each 10x outside its bound.
  EXPECT_NEAR(m.p, j.p, 0.06 * j.p);
  EXPECT_NEAR(m.rho, j.rho, 0.015 * j.rho);
  EXPECT_NEAR(m.front_speed, j.us - up, 0.04 * (j.us - up));
  EXPECT_NEAR(m.alpha, j.alpha, 0.01);
  EXPECT_LT(m.rest_speed, 0.03 * up);
  EXPECT_LT(m.energy_error, 0.01);

  // The compaction heating booked (compaction_heat, kernels/porosity/porosity.hpp) against the
  // compaction work. With v = alpha v_s the internal energy behind the shock is the matrix's
  // work plus the pores': E = w_s + q_c, w_s = -int p alpha dv_s. Pumice's matrix barely moves
  // here (rho_s from 2700 to alpha1 rho1 = 2678 kg/m^3: it expands slightly, at 0 <= p alpha
  // <= P1 alpha1), so -P1 alpha1 (1/(alpha1 rho1) - 1/rho_s0) <= w_s <= 0, at most 0.55% of E1:
  // the compaction work is E less that. Checked against the gauge's own mean E: within the w_s
  // range plus 1% of E1 (the trapezoidal booking over steps across the crush curve's kink, the
  // gauge's spread). Summed over every point (the wall layer and the front included, where the
  // matrix's share is no larger: p <= P1 throughout), sum m q_c against sum m E within 2%.
  // Against the jump's E1 = up^2/2 within 6%: the gauge's E itself is 4.7% above E1 (measured;
  // the total energy is conserved to 6e-5, so the excess sits in the plateau and is missing
  // elsewhere), which this bound covers and the booking checks above do not depend on.
  const double e1 = 0.5 * up * up;
  const double ws = j.p * j.alpha * (1.0 / (j.alpha * j.rho) - 1.0 / kBasalt.rho0);
  std::printf(
      "  compaction heat %.1f J/kg, gauge E %.1f, E1 %.1f, |w_s| <= %.1f; sums %.6g J of %.6g J\n",
      m.q, m.e, e1, ws, m.q_sum, m.e_sum);
  EXPECT_GE(m.q, m.e - 0.01 * e1);
  EXPECT_LE(m.q, m.e + ws + 0.01 * e1);
  EXPECT_NEAR(m.q_sum, m.e_sum, 0.02 * m.e_sum);
  EXPECT_NEAR(m.q, e1, 0.06 * e1);
}

}  // namespace
}  // namespace shatter

namespace shatter {
namespace {

// The same porous impact on 1 and 2 threads gives the same bits (the constitutive update is per
// point; the tail/batch split does not depend on the thread count because the scalar tail uses
// the lanes' exp and log, constitutive/simd.hpp).
TEST(PorousDeterminism, ThreadCountDoesNotChangeTheBits) {
  auto run = [](int threads) {
    const auto mat = make_material(porous_basalt(false, 1.5));
    const double rho00 = 1800.0, h = 2e-3, len = 0.05;
    ParticleStore s;
    test::add_box(s, 0, {-len, 0, 0}, {0.0, h, h}, h / 2, rho00, {500.0, 0, 0});
    test::add_box(s, 0, {0.0, 0, 0}, {len, h, h}, h / 2, rho00, {-500.0, 0, 0});
    SolverConfig cfg;
    cfg.cell_size = h;
    cfg.domain.lo = {-2 * len, 0, 0};
    cfg.domain.hi = {2 * len, h, h};
    cfg.domain.faces = {BoundaryKind::none, BoundaryKind::none, BoundaryKind::slip,
                        BoundaryKind::slip, BoundaryKind::slip, BoundaryKind::slip};
    cfg.viscosity = {0.5, 1.5};
    Simulation sim(cfg, std::move(s), {mat}, threads);
    sim.advance_to(10e-6);
    return sim.particles();
  };
  const ParticleStore a = run(1), b = run(2);
  ASSERT_EQ(a.size(), b.size());
  int compacted = 0;
  for (Field f :
       {Field::x, Field::vx, Field::rho, Field::energy, Field::pressure, Field::distension}) {
    for (std::size_t p = 0; p < a.size(); ++p) {
      ASSERT_EQ(a.col(f)[p], b.col(f)[p]) << name_of(f) << " " << p;
    }
  }
  for (std::size_t p = 0; p < a.size(); ++p) compacted += a.col(Field::distension)[p] < 1.4;
  EXPECT_GT(compacted, 20);  // the shocks have crushed part of the slabs
}

}  // namespace
}  // namespace shatter
