// The damage models by name (src/materials/damage_factory.hpp): the policy and its parameters
// from a material's damage spec, and every unknown name, unknown or missing key and out-of-range
// value an error, never a silent fallback.

#include <gtest/gtest.h>

#include <stdexcept>
#include <variant>

#include "materials/damage_factory.hpp"

namespace shatter::materials {
namespace {

using damage::Brittle;
using damage::damage_fields;
using damage::GradyKipp;
using damage::NoDamage;

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
}  // namespace shatter::materials
