// Strength and damage of the porous bulk (issue 29; kernels/porosity/porosity.hpp): the
// compaction damage against its formula and against the rate of the reference code (miluphcuda),
// the bulk deviator S = S_s / alpha of JBM08 through the whole constitutive update (elastic
// increments and the yield cap Y / alpha, several steps: no drift from the stored bulk stress),
// the sources' defaults per model, and refused values named with their key and line.

// GCC 12 false positive inside AVX-512 intrinsics (PR 105593), see constitutive/simd.hpp.
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ < 13
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "material_test_support.hpp"
#include "materials/porosity_factory.hpp"
#include "porosity/porosity.hpp"
#include "shatter/core/particles.hpp"
#include "shatter/material/catalogue.hpp"

namespace shatter {
namespace {

using porosity::Porous;

Porous palpha(double alpha0) {
  Porous m = Porous::p_alpha({alpha0, 1e6, 5e8, 2.0, 0.0});
  m.set_degradation(true, true);
  return m;
}

// The compaction damage written out from its definition (porosity.hpp): D_c^(1/3) =
// ((r + d)^(1/3) - d^(1/3)) / ((1 + d)^(1/3) - d^(1/3)), r = (alpha0 - alpha)/(alpha0 - 1).
double damage_formula(double alpha0, double alpha) {
  const double d = 0.01, r = (alpha0 - alpha) / (alpha0 - 1.0);
  const double x = (std::cbrt(r + d) - std::cbrt(d)) / (std::cbrt(1.0 + d) - std::cbrt(d));
  return x * x * x;
}

TEST(PorousDamage, CompactionDamageMatchesItsFormula) {
  const Porous m = palpha(1.8);
  EXPECT_EQ(m.compaction_damage(1.8), 0.0);  // not compacted
  // 1e-14: cube roots by exp/log (simd::vexp, vlog) against std::cbrt
  EXPECT_NEAR(m.compaction_damage(1.0), 1.0, 1e-14);  // pores closed: fully damaged
  for (double a = 1.0; a <= 1.8; a += 0.037) {
    EXPECT_NEAR(m.compaction_damage(a), damage_formula(1.8, a), 1e-14) << "alpha = " << a;
  }
  // outside [1, alpha0] (a point that expanded, or rounding below 1): clamped to [0, 1]
  EXPECT_EQ(m.compaction_damage(1.9), 0.0);
  EXPECT_NEAR(m.compaction_damage(0.999), 1.0, 1e-14);
}

TEST(PorousDamage, IntegratedFormHasTheRateOfTheReferenceCode) {
  // miluphcuda (src/internal_forces.cu, PALPHA_POROSITY) integrates the cube root of the damage
  // at the rate d(D^(1/3))/dt = -1/3 (1 - (alpha - 1)/(alpha0 - 1) + d)^(-2/3) /
  // ((1 + d)^(1/3) - d^(1/3)) / (alpha0 - 1) d(alpha)/dt, d = 0.01. Our closed form must have
  // that derivative with respect to alpha (central differences, h = 1e-6: error O(h^2) ~ 1e-10
  // relative, plus 1e-14 / h from the rounding of the values).
  const double a0 = 1.6, d = 0.01;
  const Porous m = palpha(a0);
  for (double a = 1.05; a < 1.59; a += 0.05) {
    const double h = 1e-6;
    const double num =
        (std::cbrt(m.compaction_damage(a + h)) - std::cbrt(m.compaction_damage(a - h))) / (2.0 * h);
    const double ref = -1.0 / 3.0 * std::pow(1.0 - (a - 1.0) / (a0 - 1.0) + d, -2.0 / 3.0) /
                       (std::cbrt(1.0 + d) - std::cbrt(d)) / (a0 - 1.0);
    EXPECT_NEAR(num, ref, 1e-7 * std::abs(ref)) << "alpha = " << a;
  }
}

TEST(PorousDamage, SwitchesOffGiveNoDamageAndTheMatrixDeviator) {
  const Porous m = Porous::p_alpha({1.5, 1e6, 5e8, 2.0, 0.0});  // made without the switches
  EXPECT_EQ(m.compaction_damage(1.2), 0.0);
  EXPECT_EQ(m.deviator_factor(1.2), 1.0);
  EXPECT_EQ(palpha(1.5).deviator_factor(1.2), 1.0 / 1.2);
  // alpha0 = 1 (solid): no damage whatever alpha
  EXPECT_EQ(palpha(1.0).compaction_damage(1.0), 0.0);
}

// --- through make_material: the sources' defaults, and the bulk deviator in the update --------

MaterialSpec porous_von_mises(const std::string& model, double alpha0) {
  auto s = test::spec("pvm", "tillotson", "von_mises", {});
  s.params = MaterialCatalogue::builtin().get("basalt").params;
  s.params.erase("plastic_modulus");
  s.params["yield"] = 1e8;
  s.porosity = model;
  s.params["alpha0"] = alpha0;
  if (model == "p_alpha") {
    // no compaction at the pressures of a shear test: alpha stays alpha0
    s.params.insert({{"p_e", 1e12}, {"p_s", 2e12}});
  } else {
    s.params.insert({{"eps_e", -0.5}, {"kappa", 0.98}, {"eps_x", -0.6}});
  }
  return s;
}

TEST(PorousStrength, DefaultsAreTheSources) {
  EXPECT_TRUE(materials::make_porosity(porous_von_mises("p_alpha", 1.5)).deviator_scaling());
  EXPECT_TRUE(materials::make_porosity(porous_von_mises("p_alpha", 1.5)).compaction_damage());
  EXPECT_FALSE(materials::make_porosity(porous_von_mises("eps_alpha", 1.5)).deviator_scaling());
  EXPECT_FALSE(materials::make_porosity(porous_von_mises("eps_alpha", 1.5)).compaction_damage());
  auto on = porous_von_mises("eps_alpha", 1.5);
  on.params["deviator_scaling"] = 1.0;
  on.params["compaction_damage"] = 1.0;
  EXPECT_TRUE(materials::make_porosity(on).deviator_scaling());
  EXPECT_TRUE(materials::make_porosity(on).compaction_damage());
}

constexpr FieldSet kEngine{Field::mass,    Field::rho,      Field::energy,     Field::sxx,
                           Field::syy,     Field::szz,      Field::sxy,        Field::syz,
                           Field::sxz,     Field::pressure, Field::soundspeed, Field::deps_xx,
                           Field::deps_yy, Field::deps_zz,  Field::deps_xy,    Field::deps_yz,
                           Field::deps_xz, Field::dspin_xy, Field::dspin_yz,   Field::dspin_xz};

// `steps` steps of pure shear deps_xy = g (no volume change) on 2 kWidth + 3 points (the SIMD
// batches and the scalar tail); returns the store.
ParticleStore shear(const MaterialSpec& spec, int steps, double g) {
  const auto m = make_material(spec);
  const std::size_t n = 2 * simd::kWidth + 3;
  ParticleStore s;
  s.require(kEngine);
  s.require(m->fields());
  s.add_group(0, n);
  for (std::size_t i = 0; i < n; ++i) {
    s.col(Field::rho)[i] = m->reference_density();
    s.col(Field::mass)[i] = 1e-3;
  }
  m->initialise(s, {0, n});
  for (int k = 0; k < steps; ++k) {
    for (std::size_t i = 0; i < n; ++i) s.col(Field::deps_xy)[i] = g;
    m->update(s, {0, n}, {1e-7, 1e-3, {0.0, 0.0}});
  }
  return s;
}

TEST(PorousStrength, BulkDeviatorIsTheMatrixsOverAlpha) {
  const double alpha0 = 1.5;
  for (bool scaled : {true, false}) {
    auto spec = porous_von_mises("p_alpha", alpha0);
    const double G = spec.get("young") / (2.0 * (1.0 + spec.get("poisson")));
    spec.params["deviator_scaling"] = scaled ? 1.0 : 0.0;
    const double f = scaled ? 1.0 / alpha0 : 1.0;
    // Elastic: 5 steps of 1e-6 shear, tau = 2 G (5e-6) f (no drift from re-reading the stored
    // bulk stress each step). 1e-12 relative: a few roundings.
    const auto e = shear(spec, 5, 1e-6);
    for (std::size_t i = 0; i < e.size(); ++i) {
      EXPECT_NEAR(e.col(Field::sxy)[i], 2.0 * G * 5e-6 * f, 1e-12 * G * 5e-6) << scaled << i;
      EXPECT_EQ(e.col(Field::distension)[i], alpha0);
    }
    // Plastic: far past yield, the matrix deviator sits on von Mises' sqrt(3) tau = Y, the bulk
    // one on Y f (JBM08: the porous bulk carries Y / alpha). 1e-9: the radial return's rounding.
    const auto p = shear(spec, 40, 1e-4);
    for (std::size_t i = 0; i < p.size(); ++i) {
      EXPECT_NEAR(std::sqrt(3.0) * p.col(Field::sxy)[i], 1e8 * f, 1e-9 * 1e8) << scaled << i;
    }
  }
}

// Compaction damage through the update: a P-alpha von Mises material with a Grady-Kipp damage
// model whose points have no flaws (the tensile damage D_t stays 0) is compacted under uniaxial
// strain with some shear; the borne shear stress must be the matrix deviator (the sdev column)
// times (1 - D_c(alpha)) / alpha (Eq. 14 with D = min(1, D_t + D_c), lagged coupling: D_t^n = 0).
TEST(PorousDamage, CompactionDamageReachesTheStress) {
  auto spec = porous_von_mises("p_alpha", 1.5);
  spec.params["p_e"] = 1e6;
  spec.params["p_s"] = 5e8;
  const auto m = make_material(spec, DamageSpec{"grady_kipp", {}, ""});
  const Porous por = materials::make_porosity(spec);
  const std::size_t n = 2 * simd::kWidth + 3;
  ParticleStore s;
  s.require(kEngine);
  s.require(m->fields());
  s.add_group(0, n);
  for (std::size_t i = 0; i < n; ++i) {
    s.col(Field::rho)[i] = m->reference_density();
    s.col(Field::mass)[i] = 1e-3;
  }
  m->initialise(s, {0, n});
  for (int k = 0; k < 40; ++k) {
    for (std::size_t i = 0; i < n; ++i) {
      const double dxx = -2e-3 * (1.0 + 0.05 * static_cast<double>(i));
      s.col(Field::deps_xx)[i] = dxx;
      s.col(Field::deps_xy)[i] = 2e-5;
      s.col(Field::rho)[i] /= 1.0 + dxx;
    }
    m->update(s, {0, n}, {1e-7, 1e-3, {0.0, 0.0}});
  }
  for (std::size_t i = 0; i < n; ++i) {
    const double a = s.col(Field::distension)[i];
    ASSERT_LT(a, 1.4) << i;  // compacted: D_c well above 0
    const double dc = por.compaction_damage(a);
    EXPECT_GT(dc, 0.05) << i;
    EXPECT_EQ(s.col(Field::damage)[i], 0.0) << i;  // the column keeps the tensile damage
    const double want = (1.0 - dc) * (1.0 / a) * s.col(Field::sdev_xy)[i];
    // 1e-12 relative: the kernel's own products, in another order at most
    EXPECT_NEAR(s.col(Field::sxy)[i], want, 1e-12 * std::abs(want)) << i;
    EXPECT_NE(s.col(Field::sdev_xy)[i], 0.0) << i;
  }
}

TEST(PorousStrength, SwitchOtherThanZeroOrOneIsRefusedWithKeyAndLine) {
  const auto path = std::filesystem::temp_directory_path() / "shatter_porosity_switch.toml";
  std::ofstream(path) << "[p]\nsource = \"t\"\neos = \"ideal_gas\"\nstrength = \"hydro\"\n"
                         "rho0 = 1000.0\ngamma = 1.4\n"
                         "porosity = { model = \"p_alpha\", alpha0 = 1.5, p_e = 1e6, p_s = 1e8, "
                         "compaction_damage = 0.5 }\n";
  std::string msg;
  try {
    MaterialCatalogue::load(path);
  } catch (const std::invalid_argument& e) {
    msg = e.what();
  }
  std::filesystem::remove(path);
  EXPECT_NE(msg.find(":7:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'compaction_damage'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("0 (off) or 1 (on)"), std::string::npos) << msg;
}

}  // namespace
}  // namespace shatter
