// Brittle and fatigue damage (MPM paper Sec. 3.3) and the name-to-policy factory used by
// make_material.

#include <gtest/gtest.h>

#include <stdexcept>

#include "damage/policies.hpp"
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

TEST(DamagePolicies, BuiltByNameWithParameters) {
  const AnyDamage gk = make_damage_policy(
      "grady_kipp", {{"weibull_m", 8.5}, {"rs", 1e-3}, {"intact_soundspeed", 5000.0}});
  ASSERT_TRUE(std::holds_alternative<GradyKipp>(gk));
  EXPECT_EQ(std::get<GradyKipp>(gk).params.rs, 1e-3);
  EXPECT_EQ(std::get<GradyKipp>(gk).params.intact_soundspeed, 5000.0);
  EXPECT_EQ(std::get<GradyKipp>(gk).params.crack_speed_factor, 0.4);
  EXPECT_TRUE(damage_fields(gk).has(Field::eps_min));
  const AnyDamage br = make_damage_policy("brittle", {{"sigma_0", 20e6}});
  EXPECT_EQ(std::get<Brittle>(br).params.sigma_0, 20e6);
  EXPECT_TRUE(std::holds_alternative<NoDamage>(make_damage_policy("none", {})));
  EXPECT_EQ(damage_fields(make_damage_policy("none", {})), FieldSet{});
}

TEST(DamagePolicies, UnknownNamesAndKeysAreErrors) {
  EXPECT_THROW(make_damage_policy("grady-kipp", {}), std::invalid_argument);
  EXPECT_THROW(make_damage_policy("brittle", {}), std::invalid_argument);  // sigma_0 missing
  EXPECT_THROW(make_damage_policy("brittle", {{"sigma0", 1e6}}), std::invalid_argument);
  EXPECT_THROW(make_damage_policy("fatigue", {{"eps_0", -1.0}}), std::invalid_argument);
  EXPECT_THROW(make_damage_policy("grady_kipp", {{"crack_speed", 0.4}}), std::invalid_argument);
  EXPECT_THROW(make_damage_policy("none", {{"sigma_0", 1.0}}), std::invalid_argument);
}

}  // namespace
}  // namespace shatter::damage
