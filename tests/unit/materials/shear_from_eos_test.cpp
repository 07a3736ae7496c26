// The material key shear_from_eos (kernels/strength/strength_common.hpp, ElasticConstants::
// from_eos; docs/materials.md, "Shear modulus from the EOS"): G = 3 K (1 - 2 nu) / (2 (1 + nu))
// with K = rho c_K^2 of the equation of state, iSALE's POIS option (the target of Raducan et al.
// 2019, Icarus 329, iSALE_inputs/Parameter_studies/material.inp: POIS 0.25). Constant G (key
// absent or 0) keeps the arithmetic of the constants.

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "material_test_support.hpp"
#include "materials/elastic_constants.hpp"
#include "shatter/core/particles.hpp"
#include "shatter/material/catalogue.hpp"
#include "shatter/material/probe.hpp"

namespace shatter {
namespace {

using test::kEngineFields;
using test::store_at;

constexpr double kNu = 0.25;
constexpr double kNoKey = -99.0;  // basalt(kNoKey): the material without the key

// Tillotson basalt (Benz & Asphaug 1999 as MPM paper Table 1) under Drucker-Prager with a
// cohesion far above the test's stresses: every step below is elastic.
MaterialSpec basalt(double from_eos) {
  const auto t = test::basalt_tillotson();
  MaterialSpec s = test::spec("basalt", "tillotson", "drucker_prager",
                              {{"rho0", t.rho0},
                               {"A", t.A},
                               {"B", t.B},
                               {"a", t.a},
                               {"b", t.b},
                               {"E0", t.E0},
                               {"Eiv", t.Eiv},
                               {"Ecv", t.Ecv},
                               {"rho_iv", t.rho_iv},
                               {"alpha", t.alpha},
                               {"beta", t.beta},
                               {"young", 3.0 * t.A * (1.0 - 2.0 * kNu)},
                               {"poisson", kNu},
                               {"cohesion", 1e12},
                               {"friction", 0.0},
                               {"dilatancy", 0.0},
                               {"tension_cutoff", -1e11}});
  if (from_eos != kNoKey) s.params["shear_from_eos"] = from_eos;
  return s;
}

// The EOS's c_K^2 at (rho, e) through the library's probe (not the inline EOS template: a copy
// compiled here with FMA contraction could be the one the linker keeps for the library, whose
// kernels are built without it; tests/CMakeLists.txt on porosity_test.cpp), and G of the iSALE
// formula there.
double c2_at(double rho, double e) {
  const double c = probe_eos(basalt(kNoKey), rho, e).bulk_speed;
  return c * c;
}
double g_formula(double rho, double e) {
  return 3.0 * rho * c2_at(rho, e) * (1.0 - 2.0 * kNu) / (2.0 * (1.0 + kNu));
}

// A pure shear increment gamma (tr deps = 0: rho and, from a hydrostatic start, E unchanged)
// gives s_xy = 2 G gamma (Eq. 37): G of the point.
double shear_modulus_seen(const MaterialModel& m, double rho, double e) {
  auto s = store_at(m, 1, rho, e);
  const double gamma = 1e-9;
  s.col(Field::deps_xy)[0] = gamma;
  m.update(s, {0, 1}, {1e-7, 0.1, {}});
  return s.col(Field::sxy)[0] / (2.0 * gamma);
}

TEST(ShearFromEos, ShearModulusIsThatOfTheEosBulkModulus) {
  // At the reference density, compressed, expanded and hot: G = 3 rho c^2 (1 - 2 nu) / (2 (1 +
  // nu)) with the EOS's c^2 at the point. 1e-12 relative: a few roundings of G m and s / gamma.
  const auto m = make_material(basalt(1.0));
  for (const auto& [rho, e] : {std::pair{2700.0, 0.0}, std::pair{3100.0, 1e5},
                               std::pair{2200.0, 0.0}, std::pair{2700.0, 2e6}}) {
    const double g = g_formula(rho, e);
    ASSERT_GT(g, 0.0);
    EXPECT_NEAR(shear_modulus_seen(*m, rho, e), g, 1e-12 * g) << "rho " << rho << " e " << e;
  }
}

TEST(ShearFromEos, ConstantModeKeepsTheConstantModulus) {
  // Without the key (or with 0) G = E / (2 (1 + nu)) = 3 A (1 - 2 nu) / (2 (1 + nu)) at every
  // state, compressed or not (1e-12 relative).
  const double g0 = 3.0 * 26.7e9 * (1.0 - 2.0 * kNu) / (2.0 * (1.0 + kNu));
  for (double key : {kNoKey, 0.0}) {
    const auto m = make_material(basalt(key));
    for (double rho : {2700.0, 3100.0, 2200.0}) {
      EXPECT_NEAR(shear_modulus_seen(*m, rho, 0.0), g0, 1e-12 * g0) << "rho " << rho;
    }
  }
}

// Every column's bits after a few mixed steps (compression, shear, spin) of a batch of points.
std::vector<std::uint64_t> bits_after_steps(const MaterialModel& m) {
  const std::size_t n = 11;  // a SIMD batch or more plus a scalar tail
  auto s = store_at(m, n, 2700.0, 1e4);
  std::vector<std::uint64_t> out;
  for (int step = 0; step < 5; ++step) {
    for (std::size_t i = 0; i < n; ++i) {
      const double d = 1e-4 * (1.0 + 0.1 * static_cast<double>(i));
      const Field f[9] = {Field::deps_xx,  Field::deps_yy,  Field::deps_zz,
                          Field::deps_xy,  Field::deps_yz,  Field::deps_xz,
                          Field::dspin_xy, Field::dspin_yz, Field::dspin_xz};
      const double v[9] = {-d, 0.3 * d, -0.2 * d, 0.7 * d, -0.4 * d, 0.1 * d, 0.2 * d, 0, -0.1 * d};
      for (int k = 0; k < 9; ++k) s.col(f[k])[i] = v[k];
      s.col(Field::rho)[i] /= 1.0 - 0.9 * d;
    }
    m.update(s, {0, n}, {1e-7, 0.1, {0.5, 1.0}});
  }
  for (Field f : {Field::sxx, Field::syy, Field::szz, Field::sxy, Field::syz, Field::sxz,
                  Field::pressure, Field::energy, Field::soundspeed}) {
    for (std::size_t i = 0; i < n; ++i) out.push_back(std::bit_cast<std::uint64_t>(s.col(f)[i]));
  }
  return out;
}

TEST(ShearFromEos, ZeroIsBitwiseTheDefault) {
  // shear_from_eos = 0 is the constant modulus, the same bits as a material without the key.
  EXPECT_EQ(bits_after_steps(*make_material(basalt(0.0))),
            bits_after_steps(*make_material(basalt(kNoKey))));
  // and the EOS-following modulus is not (the same steps at 2700 kg/m^3 and 10 kJ/kg, where
  // rho c^2 differs from A): the switch reaches the kernel.
  EXPECT_NE(bits_after_steps(*make_material(basalt(1.0))),
            bits_after_steps(*make_material(basalt(kNoKey))));
}

TEST(ShearFromEos, ExpandedMaterialLosesItsShearWaveSpeed) {
  // Expanded rock (rho = 300 kg/m^3, 11% of rho0, E = 1 MJ/kg: Tillotson's vapour branch at its
  // sound-speed floor c_K = 0.01 c0 = 31 m/s): with constant G the P-wave speed of Eq. 13 grows
  // like 1/sqrt(rho) (sqrt(4G/(3 rho)) = 6.0 km/s here, 42 km/s at 6 kg/m^3) and sets the time
  // step; with G from the EOS it is c_K sqrt(1 + 2 (1 - 2 nu) / (1 + nu)) = 1.342 c_K. 1e-12
  // relative; the constant-G value is 140 times above.
  const double rho = 300.0, e = 1e6;
  const double c2 = c2_at(rho, e);
  ASSERT_GT(c2, 0.0);
  const auto eos_g = make_material(basalt(1.0));
  const auto const_g = make_material(basalt(kNoKey));
  const double want = std::sqrt(c2 * (1.0 + 2.0 * (1.0 - 2.0 * kNu) / (1.0 + kNu)));
  const auto s = store_at(*eos_g, 1, rho, e);
  EXPECT_NEAR(s.col(Field::soundspeed)[0], want, 1e-12 * want);
  const auto t = store_at(*const_g, 1, rho, e);
  EXPECT_GT(t.col(Field::soundspeed)[0], 5.0 * want);
  // and the deviator's stiffness follows: G there is the formula's, not E / (2 (1 + nu))
  const double g = g_formula(rho, e);
  EXPECT_NEAR(shear_modulus_seen(*eos_g, rho, e), g, 1e-12 * g);
  EXPECT_LT(g, 0.05 * 3.0 * 26.7e9 * (1.0 - 2.0 * kNu) / (2.0 * (1.0 + kNu)));
}

TEST(ShearFromEos, BadValuesAreRefusedByName) {
  for (double v : {2.0, 0.5, -1e-3}) {
    try {
      validate(basalt(v));
      ADD_FAILURE() << "shear_from_eos = " << v << " accepted";
    } catch (const MaterialError& e) {
      EXPECT_EQ(e.key(), "shear_from_eos");
    }
  }
  // a hydrodynamic material has no shear modulus to follow the EOS
  auto h = basalt(1.0);
  h.strength = "hydro";
  for (auto k : {"cohesion", "friction", "dilatancy", "tension_cutoff"}) h.params.erase(k);
  try {
    validate(h);
    ADD_FAILURE() << "hydro with shear_from_eos = 1 accepted";
  } catch (const MaterialError& e) {
    EXPECT_EQ(e.key(), "shear_from_eos");
    EXPECT_NE(std::string(e.what()).find("hydro"), std::string::npos) << e.what();
  }
}

TEST(ShearFromEos, CatalogueErrorNamesTheLine) {
  const auto p = std::filesystem::temp_directory_path() /
                 ("shatter_shear_from_eos_" +
                  std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + ".toml");
  std::ofstream(p) << "[rock]\nsource = \"t\"\neos = \"linear_elastic\"\nstrength = \"elastic\"\n"
                      "rho0 = 2700\nyoung = 5e10\npoisson = 0.25\nshear_from_eos = 3\n";
  std::string msg;
  try {
    MaterialCatalogue::load(p);
  } catch (const std::invalid_argument& e) {
    msg = e.what();
  }
  std::filesystem::remove(p);
  EXPECT_NE(msg.find(p.string() + ":8:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'shear_from_eos'"), std::string::npos) << msg;
}

TEST(ShearFromEos, ElasticConstantsCarryTheSwitch) {
  EXPECT_FALSE(materials::elastic_constants(basalt(kNoKey)).from_eos);
  EXPECT_FALSE(materials::elastic_constants(basalt(0.0)).from_eos);
  EXPECT_TRUE(materials::elastic_constants(basalt(1.0)).from_eos);
  // constant moduli: the scale is exactly 1 at any state (the kernel's arithmetic is unchanged)
  const auto el = materials::elastic_constants(basalt(0.0));
  EXPECT_EQ(el.modulus_scale(123.0, 4.5e6), 1.0);
}

}  // namespace
}  // namespace shatter
