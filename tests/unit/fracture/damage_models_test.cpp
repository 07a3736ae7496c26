// Brittle and fatigue damage (MPM paper Sec. 3.3). The name-to-policy factory is tested with
// the material library (tests/unit/materials/damage_factory_test.cpp).

#include <gtest/gtest.h>

#include "damage/brittle.hpp"
#include "damage/fatigue.hpp"
#include "unit/fracture/lattice.hpp"

namespace shatter::damage {
namespace {

DamageInput<double> stress(double xx, double yy, double xy) {
  DamageInput<double> in{};
  in.s[0] = xx;
  in.s[1] = yy;
  in.s[3] = xy;
  in.young = 50e9;
  in.dt = 1e-8;
  return in;
}

TEST(Brittle, FailsWhenLargestPrincipalStressReachesSigma0AndStaysFailed) {
  // Pure shear tau = 30 MPa has sigma_max = 30 MPa (exact up to the round-off of the rotations,
  // hence the 1 Pa margin around sigma_0 = 40 MPa).
  Brittle b;
  b.params.sigma_0 = 40e6;
  DamageState<double> st{};
  b.evolve(stress(0, 0, 30e6), st);
  EXPECT_EQ(st.damage, 0.0);
  b.evolve(stress(0, 0, 40e6 - 1.0), st);
  EXPECT_EQ(st.damage, 0.0);
  b.evolve(stress(20e6, 20e6, 20e6 + 1.0), st);  // sigma_max = 40 MPa + 1 Pa
  EXPECT_EQ(st.damage, 1.0);
  b.evolve(stress(-1e9, 0, 0), st);  // unloading does not heal
  EXPECT_EQ(st.damage, 1.0);
}

TEST(Fatigue, DamageIsAccumulatedPlasticStrainOverEps0) {
  // D = sum(d eps_p) / eps_0: 0.01 per step with eps_0 = 0.05 gives 0.2 after 10 steps (exact
  // up to the round-off of 10 additions), then saturates at 1.
  Fatigue f;
  f.params.eps_0 = 0.05;
  DamageState<double> st{};
  DamageInput<double> in = stress(0, 0, 0);
  in.dplastic = 0.0005;
  for (int n = 0; n < 10; ++n) f.evolve(in, st);
  EXPECT_NEAR(st.damage, 0.1, 1e-15);
  in.dplastic = -0.01;  // a negative increment must not heal
  f.evolve(in, st);
  EXPECT_NEAR(st.damage, 0.1, 1e-15);
  in.dplastic = 1.0;
  f.evolve(in, st);
  EXPECT_EQ(st.damage, 1.0);
}

TEST(Fatigue, SimdLanesEqualScalarPath) {
  // Only additions, a multiplication and min/max: bit-identical.
  using B = test::Batch;
  Fatigue f;
  f.params.eps_0 = 0.3;
  DamageInput<B> in{};
  in.dplastic = B(0.0123);
  DamageState<B> st{};
  st.damage = B(0.5);
  f.evolve(in, st);
  DamageInput<double> si{};
  si.dplastic = 0.0123;
  DamageState<double> ss{};
  ss.damage = 0.5;
  f.evolve(si, ss);
  EXPECT_EQ(st.damage.get(0), ss.damage);
}

}  // namespace
}  // namespace shatter::damage
