// The composed model with the fracture area's damage policies: effective stress (Eq. 14), the
// undamaged deviator kept in sdev_*, and the columns a damaged material declares.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

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
  // Total coupling (Eq. 14 with D^{n+1}). Brittle failure at 20 MPa: one stretch of 1e-3 (sigma ~
  // 60 MPa) breaks particle 0 (D = 1), so Eq. 14 leaves sigma = -p* I with p* = (1 - D) p = 0 in
  // tension: zero stress (exact). Particle 1 is compressed: D stays 0 and its stress equals the
  // undamaged one.
  const auto m = make_material(kRock, {"brittle", {{"sigma_0", 20e6}}, "total"});
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

TEST(DamageCoupling, LaggedCouplingAppliesTheDamageOneStepLate) {
  // MPM paper Sec. 4.1.5: the damage of a step reaches the stress in the next one. The same
  // brittle break as above: in the step where D jumps to 1 the stress is still the undamaged
  // one (exactly: D^n = 0 gives factor 1); one step later, with no further strain, it is zero
  // (exactly: Eq. 14 with D = 1 in tension). Total coupling zeroes it at once (test above).
  const auto m = make_material(kRock, {"brittle", {{"sigma_0", 20e6}}, "lagged"});
  auto s = make_store(*m);
  stretch(s, 0, 1e-3);
  m->update(s, {0, 1}, {1e-7, 1e-3, {}});
  EXPECT_EQ(s.col(Field::damage)[0], 1.0);
  const double p = s.col(Field::pressure)[0];
  ASSERT_LT(p, 0.0);
  EXPECT_EQ(s.col(Field::sxy)[0], s.col(Field::sdev_xy)[0]);
  EXPECT_EQ(s.col(Field::sxx)[0], s.col(Field::sdev_xx)[0] - p);
  EXPECT_GT(s.col(Field::sxx)[0], 0.0);
  for (Field f : {Field::deps_xx, Field::deps_xy}) s.col(f)[0] = 0.0;
  m->update(s, {0, 1}, {1e-7, 1e-3, {}});
  for (Field f : {Field::sxx, Field::syy, Field::szz, Field::sxy}) {
    EXPECT_EQ(s.col(f)[0], 0.0) << name_of(f);
  }
}

TEST(DamageCoupling, IncrementalCouplingDegradesIncrementsNotTheStoredStress) {
  // MPM3D-F90 (src/Constitution.f90): the increment's modulus is (1 - D^n) G and the stored
  // deviator is not rescaled when D grows. Fatigue damage of an elastic material never grows
  // by itself, so D is set in the column. Pure shear increments (no volume change, p = 0):
  //   D = 0.5, +e:  sxy = 2 (1 - 0.5) G e / 2 (tensor shear strain e / 2 per stretch())
  //   D = 0.9, 0:   sxy unchanged (total coupling would scale it by 0.1 / 0.5)
  //   D = 0.9, -e:  sxy = (1 - 0.5) G e - (1 - 0.9) G e   (unloading with the current modulus)
  // Tolerance 1e-12 relative: a few roundings of G e.
  const auto m = make_material(kRock, {"fatigue", {{"eps_0", 1.0}}, "incremental"});
  auto s = make_store(*m);
  const double G = 53.1e9 / (2.0 * 1.15), e = 1e-4;
  auto shear = [&](double de, double D) {
    s.col(Field::damage)[0] = D;
    s.col(Field::deps_xy)[0] = 0.5 * de;
    m->update(s, {0, 1}, {1e-7, 1e-3, {}});
    return s.col(Field::sxy)[0];
  };
  const double tol = 1e-12 * G * e;
  EXPECT_NEAR(shear(e, 0.5), 0.5 * G * e, tol);
  EXPECT_NEAR(shear(0.0, 0.9), 0.5 * G * e, tol);
  EXPECT_NEAR(shear(-e, 0.9), 0.5 * G * e - 0.1 * G * e, tol);
  // The undamaged deviator (sdev, what the damage policy reads) took the full G: G e - G e = 0.
  EXPECT_NEAR(s.col(Field::sdev_xy)[0], 0.0, tol);
}

TEST(DamageCoupling, UnknownCouplingIsAnErrorNamingTheKey) {
  try {
    make_material(kRock, {"brittle", {{"sigma_0", 20e6}}, "instant"});
    FAIL() << "no error for coupling = instant";
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("'coupling'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("'instant'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("lagged"), std::string::npos) << msg;
  }
}

// Fully damaged rock (D = 1) under confinement, sheared far past yield in one step: the stress
// it keeps must be the damaged branch of its yield surface, not zero (issue 11 item 1: Eq. 14's
// (1 - D) applied on top of a yield surface that already carries D left fully damaged rock no
// shear strength at any pressure). One step from rest: volumetric strain -3e-3 (p ~ 75 MPa via
// the EOS) and tensor shear strain 5e-3 (trial tau = 2 G 5e-3 = 230 MPa, far above the damaged
// strength, ~60-100 MPa).
// Viscosity is off (ConstitutiveContext defaults) so the stress is the material's.
struct ConfinedShear {
  double tau;  // sqrt(J2) of the stored stress
  double p;    // pressure of the stored stress (compression > 0)
};
ConfinedShear confined_shear(const MaterialModel& m, double D) {
  auto s = make_store(m);
  s.col(Field::damage)[0] = D;
  for (Field f : {Field::deps_xx, Field::deps_yy, Field::deps_zz}) s.col(f)[0] = -1e-3;
  s.col(Field::deps_xy)[0] = 5e-3;
  s.col(Field::rho)[0] /= 1.0 - 3e-3;
  m.update(s, {0, 1}, {1e-7, 1e-3, {}});
  const double sig[6] = {s.col(Field::sxx)[0], s.col(Field::syy)[0], s.col(Field::szz)[0],
                         s.col(Field::sxy)[0], s.col(Field::syz)[0], s.col(Field::sxz)[0]};
  const double p = -(sig[0] + sig[1] + sig[2]) / 3.0;
  const double j2 = 0.5 * ((sig[0] + p) * (sig[0] + p) + (sig[1] + p) * (sig[1] + p) +
                           (sig[2] + p) * (sig[2] + p)) +
                    sig[3] * sig[3] + sig[4] * sig[4] + sig[5] * sig[5];
  return {std::sqrt(j2), p};
}

TEST(DamageCoupling, FullyDamagedModifiedLundborgKeepsGranularFrictionUnderConfinement) {
  // The catalogue's basalt_lab_lundborg (MPM paper Table 4, Y0 = 60 MPa, mu_d = 0.8,
  // Ym = 3.5 GPa, dilatancy 0.256; Tillotson EOS). At D = 1 Eq. 4 leaves
  //   tau = mu_d p / (1 + mu_d p / Ym)
  // at the pressure p after the dilatant correction (Eq. 5b). Tolerance 1e-9 relative: the
  // Newton return of Eq. 5a/5b converges to round-off (modified_lundborg.hpp, 12 iterations).
  // With total and lagged coupling (D^n = D^{n+1} = 1 here) alike.
  const MaterialSpec rock = MaterialCatalogue::builtin().get("basalt_lab_lundborg");
  for (const char* coupling : {"total", "lagged"}) {
    const auto m = make_material(rock, {"fatigue", {{"eps_0", 1.0}}, coupling});
    const auto r = confined_shear(*m, 1.0);
    ASSERT_GT(r.p, 10e6) << coupling;
    const double mu_d = 0.8, ym = 3.5e9;
    const double expected = mu_d * r.p / (1.0 + mu_d * r.p / ym);
    EXPECT_NEAR(r.tau, expected, 1e-9 * expected) << coupling << " p = " << r.p;
  }
}

TEST(DamageCoupling, FullyDamagedLundborgKeepsDryFrictionUnderConfinement) {
  // Lundborg / Collins (MPM paper Eqs. 47-49): at D = 1, tau = min(mu_d p, Y_i(p)) (Eq. 48) at
  // the EOS pressure (the simplified return leaves p alone). Linear elastic EOS, K from E and
  // nu. Tolerance 1e-12 relative: the return is one scaling by Y / tau*.
  const MaterialSpec rock = test::spec("rock", "linear_elastic", "lundborg",
                                       {{"rho0", 2700.0},
                                        {"young", 53.1e9},
                                        {"poisson", 0.15},
                                        {"cohesion", 60e6},
                                        {"friction_intact", 1.5},
                                        {"friction_damaged", 0.8},
                                        {"strength_limit", 3.5e9}});
  const auto m = make_material(rock, {"fatigue", {{"eps_0", 1.0}}, "total"});
  const auto r = confined_shear(*m, 1.0);
  ASSERT_GT(r.p, 10e6);
  const double yi = 60e6 + 1.5 * r.p / (1.0 + 1.5 * r.p / (3.5e9 - 60e6));
  const double expected = std::min(0.8 * r.p, yi);
  EXPECT_NEAR(r.tau, expected, 1e-12 * expected) << "p = " << r.p;
}

TEST(DamageCoupling, DamageOnMaterialWithoutYoungIsAnError) {
  EXPECT_THROW(
      make_material(MaterialCatalogue::builtin().get("water_ice"), {"brittle", {{"sigma_0", 1e6}}}),
      std::invalid_argument);
}

}  // namespace
}  // namespace shatter
