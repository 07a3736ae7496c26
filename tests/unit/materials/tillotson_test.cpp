// Tillotson EOS (MPM paper Eqs. 8-12): region values, continuity, sound speed.

#include "eos/tillotson.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "material_test_support.hpp"

namespace shatter {
namespace {

using eos::Tillotson;
using eos::TillotsonRegion;

// Reference values were computed by hand from Eqs. 8-11 (independent Python evaluation of the
// printed formulas with the Table 1 basalt). Tolerance 1e-12 relative: the kernel and the
// reference evaluate the same closed form in a different order, so they agree to a few ulp
// times the cancellation in A mu + B mu^2 (< 10).
constexpr double kRel = 1e-12;

struct RegionCase {
  double rho, e, p;
  TillotsonRegion region;
};

TEST(Tillotson, EachRegionMatchesHandComputedPressure) {
  const Tillotson t(test::basalt_tillotson());
  const RegionCase cases[] = {
      {3000.0, 1e6, 9288824124.754099, TillotsonRegion::compressed},          // Eq. 8
      {2500.0, 2e6, 8132969472.473203, TillotsonRegion::cold_expanded},       // Eq. 8
      {2500.0, 1e7, 47054178326.10362, TillotsonRegion::mixed},               // Eq. 10
      {2500.0, 3e7, 137869011167.0472, TillotsonRegion::hot_expanded},        // Eq. 9
      {1000.0, 3e7, 15000016463.351675, TillotsonRegion::hot_expanded},       // Eq. 9 below rho_iv
      {1500.0, 1.5e7, 30070880009.95768, TillotsonRegion::vapour_expansion},  // Eq. 11
  };
  for (const auto& c : cases) {
    EXPECT_EQ(t.region(c.rho, c.e), c.region) << c.rho << " " << c.e;
    EXPECT_NEAR(t.evaluate(c.rho, c.e).p, c.p, kRel * std::abs(c.p)) << c.rho << " " << c.e;
  }
}

TEST(Tillotson, ColdVapourStateIsHeldAtThePressureFloor) {
  // Eq. 11 at rho = 1000, E = 0 gives A mu = -16.8 GPa; the documented floor is
  // A mu_iv rho/rho_iv = -3.4611 GPa (exact arithmetic, so 1e-14 relative).
  const Tillotson t(test::basalt_tillotson());
  const double floor = 26.7e9 * (2000.0 / 2700.0 - 1.0) * 1000.0 / 2000.0;
  EXPECT_NEAR(t.evaluate(1000.0, 0.0).p, floor, 1e-14 * std::abs(floor));
  EXPECT_DOUBLE_EQ(t.pressure_floor(1000.0), floor);
  // rho -> 0: the tension vanishes with the density (floor slope * rho, 1e-14 relative).
  EXPECT_NEAR(t.evaluate(1e-6, 0.0).p, floor * 1e-9, 1e-14 * std::abs(floor) * 1e-9);
}

TEST(Tillotson, PressureIsContinuousAcrossRegionBorders) {
  // The borders rho = rho0, E = Eiv and E = Ecv (rho >= rho_iv) are continuous by construction
  // of Eqs. 8-10. A step of 1e-9 relative across a border changes p by |dp| ~ 1e-9 * (rho dp/drho
  // or E dp/dE) <= 1e-9 * 1e11 Pa, so a jump above 1e3 Pa would be a real discontinuity.
  const Tillotson t(test::basalt_tillotson());
  const auto& q = t.params();
  const double eps = 1e-9;
  for (double e : {0.0, 1e6, 4e6, 1e7, 2e7, 5e7}) {  // across rho = rho0
    EXPECT_NEAR(t.evaluate(q.rho0 * (1 - eps), e).p, t.evaluate(q.rho0 * (1 + eps), e).p, 1e3)
        << "E=" << e;
  }
  for (double rho : {2000.0, 2200.0, 2500.0, 2699.0}) {
    EXPECT_NEAR(t.evaluate(rho, q.Eiv * (1 - eps)).p, t.evaluate(rho, q.Eiv * (1 + eps)).p, 1e3)
        << "Eiv, rho=" << rho;
    EXPECT_NEAR(t.evaluate(rho, q.Ecv * (1 - eps)).p, t.evaluate(rho, q.Ecv * (1 + eps)).p, 1e3)
        << "Ecv, rho=" << rho;
  }
}

TEST(Tillotson, JumpAtIncipientVaporisationDensityIsTheBTerm) {
  // Eq. 11 drops B mu^2 of Eq. 8, so the formulation itself jumps by B mu_iv^2 at rho_iv for
  // E <= Eiv (documented in docs/materials.md). Checked to 1e-6 relative of the jump (the 1e-9
  // step contributes ~1e-9 * rho dp/drho ~ 30 Pa out of 1.8 GPa).
  const Tillotson t(test::basalt_tillotson());
  const double mu_iv = 2000.0 / 2700.0 - 1.0;
  const double jump = 26.7e9 * mu_iv * mu_iv;
  for (double e : {1e6, 4e6}) {
    const double above = t.evaluate(2000.0 * (1 + 1e-9), e).p;
    const double below = t.evaluate(2000.0 * (1 - 1e-9), e).p;
    EXPECT_NEAR(above - below, jump, 1e-6 * jump) << e;
  }
}

TEST(Tillotson, SoundSpeedMatchesEq12ByFiniteDifferences) {
  // Analytic derivatives of each branch against central differences (step 1e-6 relative:
  // truncation ~1e-12 relative, round-off ~1e-10 relative of rho dp/drho), so 1e-6 relative
  // catches any wrong term while leaving room for both errors.
  const Tillotson t(test::basalt_tillotson());
  const double states[][2] = {{3000, 1e6}, {4000, 5e7},   {2500, 2e6},   {2500, 1e7},
                              {2500, 3e7}, {1000, 3e7},   {1500, 1.5e7}, {2200, 4.0e6},
                              {500, 1e8},  {2699, 18.3e6}};
  for (const auto& s : states) {
    const double c2 = t.evaluate(s[0], s[1]).c2;
    const double fd = test::c2_by_differences(t, s[0], s[1]);
    EXPECT_NEAR(c2, fd, 1e-6 * std::abs(fd)) << "rho=" << s[0] << " E=" << s[1];
  }
}

TEST(Tillotson, SoundSpeedIsPositiveAndFiniteOnDenseSweep) {
  // The whole (rho, E) plane a run can visit: 1e-3 rho0 .. 3 rho0, 0 .. 10 Ecv (and a few
  // extreme corners). c^2 must be finite and at least the documented floor (1% of c0)^2.
  const Tillotson t(test::basalt_tillotson());
  const double floor = 1e-4 * 26.7e9 / 2700.0;
  int n = 0;
  for (int i = 0; i <= 400; ++i) {
    const double rho = 2700.0 * std::pow(10.0, -3.0 + (3.0 + std::log10(3.0)) * i / 400.0);
    for (int j = 0; j <= 400; ++j) {
      const double e = 10.0 * 18.2e6 * j / 400.0;
      const auto pt = t.evaluate(rho, e);
      ASSERT_TRUE(std::isfinite(pt.p)) << rho << " " << e;
      ASSERT_TRUE(std::isfinite(pt.c2)) << rho << " " << e;
      ASSERT_GE(pt.c2, floor * (1 - 1e-15)) << rho << " " << e;
      ++n;
    }
  }
  for (double rho : {0.0, 1e-300, 1e5, 1e7}) {
    for (double e : {-1e7, 0.0, 1e12}) {
      const auto pt = t.evaluate(rho, e);
      EXPECT_TRUE(std::isfinite(pt.p) && std::isfinite(pt.c2) && pt.c2 > 0.0) << rho << " " << e;
    }
  }
  EXPECT_EQ(n, 401 * 401);
}

TEST(Tillotson, ClassicFormulationWithoutVapourBranch) {
  // rho_iv = 0: expanded cold states use Eq. 8 down to any density (Benz & Asphaug 1999).
  auto q = test::basalt_tillotson();
  q.rho_iv = 0.0;
  const Tillotson t(q);
  EXPECT_EQ(t.region(1000.0, 1e6), TillotsonRegion::cold_expanded);
  const double mu = 1000.0 / 2700.0 - 1.0;
  const double w = 1e6 / (487e6 * (1000.0 / 2700.0) * (1000.0 / 2700.0)) + 1.0;
  const double p = (0.5 + 1.5 / w) * 1000.0 * 1e6 + 26.7e9 * mu + 26.7e9 * mu * mu;
  EXPECT_NEAR(t.evaluate(1000.0, 1e6).p, p, kRel * std::abs(p));
}

}  // namespace
}  // namespace shatter
