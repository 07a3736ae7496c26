// The composed model with the fracture area's damage policies: effective stress (Eq. 14), the
// undamaged deviator kept in sdev_*, and the columns a damaged material declares.

#include <gtest/gtest.h>

#include <cmath>

#include "material_test_support.hpp"
#include "shatter/core/particles.hpp"
#include "shatter/material/catalogue.hpp"

namespace shatter {
namespace {

constexpr FieldSet kEngineFields =
    kStress | kStrainIncrement | kSpinIncrement |
    FieldSet{Field::mass, Field::rho, Field::energy, Field::pressure, Field::soundspeed};

const MaterialSpec kRock = test::spec("rock", "linear_elastic", "elastic",
                                      {{"rho0", 2700.0}, {"young", 53.1e9}, {"poisson", 0.15}});

ParticleStore make_store(const MaterialModel& m) {
  ParticleStore s;
  s.require(kEngineFields);
  s.require(m.fields());
  s.add_group(0, 2);
  for (std::size_t i = 0; i < 2; ++i) {
    s.col(Field::rho)[i] = 2700.0;
    s.col(Field::mass)[i] = 1e-6;
  }
  m.initialise(s, {0, 2});
  return s;
}

void stretch(ParticleStore& s, std::size_t i, double e) {
  s.col(Field::deps_xx)[i] = e;
  s.col(Field::deps_xy)[i] = 0.5 * e;
  s.col(Field::rho)[i] /= 1.0 + e;
}

TEST(DamageCoupling, DamagedMaterialDeclaresItsColumns) {
  const auto gk = make_material(kRock, {"grady_kipp", {}});
  for (Field f : {Field::damage, Field::eps_min, Field::n_flaws, Field::sdev_xx, Field::sdev_xz})
    EXPECT_TRUE(gk->fields().has(f)) << name_of(f);
  const auto none = make_material(kRock);
  EXPECT_FALSE(none->fields().has(Field::sdev_xx));
}

TEST(DamageCoupling, FullyDamagedMaterialCarriesNoTensionButKeepsCompression) {
  // Brittle failure at 20 MPa: one stretch of 1e-3 (sigma ~ 60 MPa) breaks particle 0 (D = 1),
  // so Eq. 14 leaves sigma = -p* I with p* = (1 - D) p = 0 in tension: zero stress (exact).
  // Particle 1 is compressed: D stays 0 and its stress equals the undamaged one.
  const auto m = make_material(kRock, {"brittle", {{"sigma_0", 20e6}}});
  auto s = make_store(*m);
  stretch(s, 0, 1e-3);
  stretch(s, 1, -1e-3);
  m->update(s, {0, 2}, {1e-7, 1e-3, {}});
  EXPECT_EQ(s.col(Field::damage)[0], 1.0);
  for (Field f : {Field::sxx, Field::syy, Field::szz, Field::sxy}) {
    EXPECT_EQ(s.col(f)[0], 0.0) << name_of(f);
  }
  // The undamaged deviator is kept for the next step (sdev), and differs from the stress.
  EXPECT_GT(s.col(Field::sdev_xx)[0], 0.0);
  EXPECT_EQ(s.col(Field::damage)[1], 0.0);
  EXPECT_LT(s.col(Field::sxx)[1], 0.0);
  EXPECT_NEAR(s.col(Field::sxx)[1], s.col(Field::sdev_xx)[1] - s.col(Field::pressure)[1],
              1e-9 * std::abs(s.col(Field::sxx)[1]));
}

TEST(DamageCoupling, PartialDamageScalesDeviatorAndTensileMeanStress) {
  // Eq. 14 with D = 0.5 set in the column (the fatigue policy never lowers D and adds nothing
  // for an elastic material): deviator halved, tensile pressure halved (1e-12 relative).
  const auto m = make_material(kRock, {"fatigue", {{"eps_0", 1.0}}});
  auto s = make_store(*m);
  s.col(Field::damage)[0] = 0.5;
  stretch(s, 0, 1e-3);
  m->update(s, {0, 1}, {1e-7, 1e-3, {}});
  const double p = s.col(Field::pressure)[0];
  ASSERT_LT(p, 0.0);
  EXPECT_NEAR(s.col(Field::sxy)[0], 0.5 * s.col(Field::sdev_xy)[0], 1e-12 * std::abs(p));
  EXPECT_NEAR(s.col(Field::sxx)[0], 0.5 * (s.col(Field::sdev_xx)[0] - p), 1e-12 * std::abs(p));
}

TEST(DamageCoupling, DamageOnMaterialWithoutYoungIsAnError) {
  EXPECT_THROW(
      make_material(MaterialCatalogue::builtin().get("water_ice"), {"brittle", {{"sigma_0", 1e6}}}),
      std::invalid_argument);
}

}  // namespace
}  // namespace shatter
