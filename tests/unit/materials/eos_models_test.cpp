// The non-Tillotson equations of state: hand values, Eq. 12 sound speed, guards.

#include <gtest/gtest.h>

#include <cmath>

#include "eos/ideal_gas.hpp"
#include "eos/linear_elastic.hpp"
#include "eos/linear_polynomial.hpp"
#include "eos/mie_gruneisen.hpp"
#include "eos/tillotson_simplified.hpp"
#include "material_test_support.hpp"

namespace shatter {
namespace {

// Closed forms evaluated in a different order: a few ulp, 1e-13 relative.
constexpr double kRel = 1e-13;
// Finite-difference check of Eq. 12 (see tillotson_test.cpp for the error budget).
constexpr double kFd = 1e-6;

TEST(TillotsonSimplified, PressureAndSoundSpeed) {
  const eos::TillotsonSimplified t({2700.0, 26.7e9, 0.5, 1.5});
  // p = (a + b) rho E + A mu at rho = 3000, E = 1e6: 2 * 3e9 + 26.7e9 / 9.
  const double p = 2.0 * 3000.0 * 1e6 + 26.7e9 * (3000.0 / 2700.0 - 1.0);
  EXPECT_NEAR(t.evaluate(3000.0, 1e6).p, p, kRel * p);
  EXPECT_NEAR(t.evaluate(3000.0, 1e6).c2, test::c2_by_differences(t, 3000.0, 1e6),
              kFd * t.evaluate(3000.0, 1e6).c2);
  // c^2 at the reference state is A / rho0 exactly (E = 0, p = 0).
  EXPECT_NEAR(t.evaluate(2700.0, 0.0).c2, 26.7e9 / 2700.0, kRel * 26.7e9 / 2700.0);
}

TEST(MieGruneisen, ReferenceHugoniotAndSoundSpeed) {
  const double rho0 = 2703.0, c0 = 5240.0, s = 1.4, g0 = 1.97;
  const eos::MieGruneisen m({rho0, c0, s, g0});
  // On the reference Hugoniot (E = E_H) the pressure is p_H = rho0 c0^2 chi / (1 - s chi)^2.
  const double chi = 0.2, rho = rho0 / (1.0 - chi);
  const double ph = rho0 * c0 * c0 * chi / ((1.0 - s * chi) * (1.0 - s * chi));
  const double eh = ph * chi / (2.0 * rho0);
  EXPECT_NEAR(m.evaluate(rho, eh).p, ph, kRel * ph);
  // Off the Hugoniot the thermal part is Gamma0 rho0 (E - E_H).
  EXPECT_NEAR(m.evaluate(rho, eh + 1e6).p, ph + g0 * rho0 * 1e6, kRel * ph);
  EXPECT_NEAR(m.evaluate(rho, eh).c2, test::c2_by_differences(m, rho, eh), kFd * c0 * c0 * 4);
  EXPECT_NEAR(m.evaluate(rho0, 0.0).c2, c0 * c0, kRel * c0 * c0);
  // Expansion: linear reference curve.
  const double rho_e = 2000.0, chi_e = 1.0 - rho0 / rho_e;
  EXPECT_NEAR(m.evaluate(rho_e, 0.0).p, rho0 * c0 * c0 * chi_e * (1.0 - 0.5 * g0 * chi_e),
              kRel * rho0 * c0 * c0);
}

TEST(MieGruneisen, RunawayCompressionStaysFinite) {
  // Past chi = 0.9/s the Hugoniot continues as its tangent: p and c finite and compressive,
  // and p continuous at chi_max (the tangent starts at the curve's value: 1e-9 relative).
  const eos::MieGruneisen m({2703.0, 5240.0, 1.4, 1.97});
  for (double ratio : {2.0, 3.0, 3.4, 3.5, 10.0, 1e3, 1e6}) {
    const auto pt = m.evaluate(2703.0 * ratio, 0.0);
    EXPECT_TRUE(std::isfinite(pt.p) && std::isfinite(pt.c2) && pt.c2 > 0.0) << ratio;
    EXPECT_GT(pt.p, 0.0) << ratio;
  }
  const double rho_max = 2703.0 / (1.0 - 0.9 / 1.4);
  const double below = m.evaluate(rho_max * (1 - 1e-12), 0.0).p;
  const double above = m.evaluate(rho_max * (1 + 1e-12), 0.0).p;
  EXPECT_NEAR(below, above, 1e-9 * below);
}

TEST(LinearPolynomial, PolynomialWithQuadraticTermsOnlyInCompression) {
  eos::LinearPolynomialParams q;
  q.rho0 = 2000.0;
  const double C[7] = {1e5, 30e9, 10e9, 5e9, 0.4, 0.3, 0.2};
  for (int k = 0; k < 7; ++k) q.C[k] = C[k];
  const eos::LinearPolynomial lp(q);
  const double mu = 0.1, e = 2e6, rho = 2200.0;
  const double p = C[0] + C[1] * mu + C[2] * mu * mu + C[3] * mu * mu * mu +
                   (C[4] + C[5] * mu + C[6] * mu * mu) * 2000.0 * e;
  EXPECT_NEAR(lp.evaluate(rho, e).p, p, kRel * p);
  const double mun = -0.1, rhon = 1800.0;
  const double pn = C[0] + C[1] * mun + C[3] * mun * mun * mun + (C[4] + C[5] * mun) * 2000.0 * e;
  EXPECT_NEAR(lp.evaluate(rhon, e).p, pn, kRel * std::abs(pn) + 1e-3);
  EXPECT_NEAR(lp.evaluate(rho, e).c2, test::c2_by_differences(lp, rho, e),
              kFd * lp.evaluate(rho, e).c2);
  EXPECT_NEAR(lp.evaluate(rhon, e).c2, test::c2_by_differences(lp, rhon, e),
              kFd * lp.evaluate(rhon, e).c2);
}

TEST(LinearElastic, BulkModulusLaw) {
  const eos::LinearElastic le({2700.0, 30e9});
  EXPECT_NEAR(le.evaluate(2727.0, 123.0).p, 30e9 * 0.01, 1e-12 * 30e9 * 0.01);
  EXPECT_DOUBLE_EQ(le.evaluate(1.0, 0.0).c2, 30e9 / 2700.0);
}

TEST(IdealGas, PressureAndAdiabaticSoundSpeed) {
  const eos::IdealGas g({1.0, 1.4});
  // Sod left state: rho = 1, p = 1 -> E = p / ((gamma - 1) rho) = 2.5, c^2 = gamma p / rho.
  const auto pt = g.evaluate(1.0, 2.5);
  EXPECT_NEAR(pt.p, 1.0, kRel);
  EXPECT_NEAR(pt.c2, 1.4, kRel);
  EXPECT_NEAR(pt.c2, test::c2_by_differences(g, 1.0, 2.5), kFd);
  // Negative energy reads as vacuum: no tension, no imaginary sound speed.
  EXPECT_EQ(g.evaluate(1.0, -1.0).p, 0.0);
  EXPECT_EQ(g.evaluate(1.0, -1.0).c2, 0.0);
}

TEST(EosGuards, ExtremeStatesGiveFiniteOutput) {
  // p ~ 1 TPa and beyond, rho -> 0, negative energy: every EOS returns finite p and c^2 >= 0.
  const eos::TillotsonSimplified ts({2700.0, 26.7e9, 0.5, 1.5});
  const eos::MieGruneisen mg({2703.0, 5240.0, 1.4, 1.97});
  eos::LinearPolynomialParams q;
  q.rho0 = 2000.0;
  q.C[1] = 30e9;
  q.C[2] = 10e9;
  const eos::LinearPolynomial lp(q);
  for (double rho : {0.0, 1e-300, 1e-3, 1e4, 1e6}) {
    for (double e : {-1e9, 0.0, 1e6, 1e12}) {
      for (const auto& pt : {ts.evaluate(rho, e), mg.evaluate(rho, e), lp.evaluate(rho, e)}) {
        EXPECT_TRUE(std::isfinite(pt.p)) << rho << " " << e;
        EXPECT_TRUE(std::isfinite(pt.c2) && pt.c2 > 0.0) << rho << " " << e;
      }
    }
  }
}

}  // namespace
}  // namespace shatter
