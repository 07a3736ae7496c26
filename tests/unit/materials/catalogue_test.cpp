// Material catalogue (data/materials.toml) and parameter validation: every kind of bad input
// fails loudly and names the key (and, from a file, the file and line).

#include "shatter/material/catalogue.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include "material_test_support.hpp"
#include "materials/model_factory.hpp"

namespace shatter {
namespace {

std::string error_of(const MaterialSpec& s) {
  try {
    validate(s);
  } catch (const MaterialError& e) {
    return std::string(e.what()) + " [key=" + e.key() + "]";
  }
  return "";
}

MaterialSpec good_basalt() {
  return MaterialCatalogue::builtin().get("basalt");
}

TEST(Catalogue, BuiltinHoldsThePaperMaterialsWithSources) {
  const auto cat = MaterialCatalogue::builtin();
  for (const char* n : {"basalt", "nylon", "basalt_asteroid", "basalt_asteroid_lundborg",
                        "basalt_lab_lundborg", "granite", "water_ice", "iron", "sod_gas"}) {
    ASSERT_TRUE(cat.contains(n)) << n;
    EXPECT_FALSE(cat.get(n).source.empty()) << n;
    EXPECT_NO_THROW(make_material(cat.get(n))) << n;
  }
  // The unit trap: E0 of basalt is 487 MJ/kg.
  EXPECT_DOUBLE_EQ(cat.get("basalt").get("E0"), 487e6);
  EXPECT_DOUBLE_EQ(cat.get("basalt_asteroid_lundborg").get("cohesion"), 90e6);
}

TEST(Catalogue, UnknownMaterialListsKnownNames) {
  const auto cat = MaterialCatalogue::builtin();
  try {
    cat.get("basalite");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("basalt"), std::string::npos) << e.what();
  }
}

TEST(Validation, UnknownEosNameListsKnownModels) {
  auto s = good_basalt();
  s.eos = "tilotson";
  const auto msg = error_of(s);
  EXPECT_NE(msg.find("tilotson"), std::string::npos) << msg;
  EXPECT_NE(msg.find("mie_gruneisen"), std::string::npos) << msg;
  EXPECT_NE(msg.find("key=eos"), std::string::npos) << msg;
}

TEST(Validation, UnknownStrengthName) {
  auto s = good_basalt();
  s.strength = "mohr";
  EXPECT_NE(error_of(s).find("key=strength"), std::string::npos);
}

TEST(Validation, UnknownParameterKey) {
  auto s = good_basalt();
  s.params["E_0"] = 1.0;
  const auto msg = error_of(s);
  EXPECT_NE(msg.find("key=E_0"), std::string::npos) << msg;
}

TEST(Validation, MissingRequiredKey) {
  auto s = good_basalt();
  s.params.erase("Ecv");
  EXPECT_NE(error_of(s).find("key=Ecv"), std::string::npos);
}

TEST(Validation, NonPositiveModulus) {
  auto s = good_basalt();
  s.params["young"] = -1.0;
  EXPECT_NE(error_of(s).find("key=young"), std::string::npos);
  s = good_basalt();
  s.params["A"] = 0.0;
  EXPECT_NE(error_of(s).find("key=A"), std::string::npos);
}

TEST(Validation, PoissonOutOfRange) {
  auto s = good_basalt();
  s.params["poisson"] = 0.5;
  EXPECT_NE(error_of(s).find("key=poisson"), std::string::npos);
}

TEST(Validation, IncipientVaporisationAboveReferenceDensity) {
  auto s = good_basalt();
  s.params["rho_iv"] = 2800.0;
  EXPECT_NE(error_of(s).find("key=rho_iv"), std::string::npos);
}

TEST(Validation, IncipientAboveCompleteVaporisationEnergy) {
  auto s = good_basalt();
  s.params["Eiv"] = 20e6;
  EXPECT_NE(error_of(s).find("key=Eiv"), std::string::npos);
}

TEST(Validation, NonFiniteValue) {
  auto s = good_basalt();
  s.params["B"] = std::nan("");
  EXPECT_NE(error_of(s).find("key=B"), std::string::npos);
}

TEST(Validation, DruckerPragerCutOffBeyondApex) {
  const auto s = test::spec("dp", "linear_elastic", "drucker_prager",
                            {{"rho0", 2000},
                             {"young", 1e9},
                             {"poisson", 0.25},
                             {"cohesion", 1e6},
                             {"friction", 0.5},
                             {"dilatancy", 0.1},
                             {"tension_cutoff", -5e6}});
  EXPECT_NE(error_of(s).find("key=tension_cutoff"), std::string::npos);
}

TEST(Validation, LundborgLimitBelowCohesion) {
  auto s = MaterialCatalogue::builtin().get("basalt_asteroid_lundborg");
  s.params["strength_limit"] = 50e6;
  EXPECT_NE(error_of(s).find("key=strength_limit"), std::string::npos);
}

TEST(Validation, LundborgTensionCutOffMustNotBePositive) {
  // tension_cutoff (optional, lundborg and modified_lundborg): p_t <= 0; 0 and -1 MPa pass.
  for (const char* name : {"basalt_asteroid_lundborg", "basalt_lab_lundborg"}) {
    auto s = MaterialCatalogue::builtin().get(name);
    s.params["tension_cutoff"] = 1e6;
    EXPECT_NE(error_of(s).find("key=tension_cutoff"), std::string::npos) << name;
    for (double pt : {0.0, -1e6}) {
      s.params["tension_cutoff"] = pt;
      EXPECT_EQ(error_of(s), "") << name;
    }
  }
}

TEST(Factory, LundborgTensionCutOffOnlyWithTheKey) {
  for (const char* name : {"basalt_asteroid_lundborg", "basalt_lab_lundborg"}) {
    auto s = MaterialCatalogue::builtin().get(name);
    const bool ml = s.strength == "modified_lundborg";
    auto cut = [&](const materials::AnyStrength& a) {
      return ml ? std::get<strength::ModifiedLundborg>(a).tension_cutoff
                : std::get<strength::Lundborg>(a).tension_cutoff;
    };
    EXPECT_EQ(cut(materials::make_strength(s)), -std::numeric_limits<double>::infinity()) << name;
    s.params["tension_cutoff"] = -2e6;
    EXPECT_EQ(cut(materials::make_strength(s)), -2e6) << name;
  }
}

TEST(Validation, IdealGasGammaAtMostOne) {
  const auto s = test::spec("g", "ideal_gas", "hydro", {{"rho0", 1.0}, {"gamma", 1.0}});
  EXPECT_NE(error_of(s).find("key=gamma"), std::string::npos);
}

TEST(Validation, MissingDensity) {
  const auto s = test::spec("g", "ideal_gas", "hydro", {{"gamma", 1.4}});
  EXPECT_NE(error_of(s).find("key=rho0"), std::string::npos);
}

TEST(Validation, UnknownDamageModelIsAnErrorNotAFallback) {
  try {
    make_material(good_basalt(), DamageSpec{"grady", {}});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("grady_kipp"), std::string::npos) << e.what();
  }
}

class CatalogueFile : public ::testing::Test {
 protected:
  std::filesystem::path write(const std::string& text) {
    path_ =
        std::filesystem::temp_directory_path() /
        ("shatter_catalogue_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
         "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".toml");
    std::ofstream(path_) << text;
    return path_;
  }
  void TearDown() override { std::filesystem::remove(path_); }
  std::filesystem::path path_;
};

std::string load_error(const std::filesystem::path& p) {
  try {
    MaterialCatalogue::load(p);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST_F(CatalogueFile, ErrorNamesFileLineAndKey) {
  const auto p = write(
      "[gas]\n"
      "source = \"test\"\n"
      "eos = \"ideal_gas\"\n"
      "strength = \"hydro\"\n"
      "rho0 = 1.0\n"
      "gamma = 0.5\n");
  const auto msg = load_error(p);
  EXPECT_NE(msg.find(p.string() + ":6:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'gamma'"), std::string::npos) << msg;
}

TEST_F(CatalogueFile, LundborgTensionCutOffAboveZeroNamesLineAndKey) {
  const auto p = write(
      "[sand]\n"
      "source = \"test\"\n"
      "eos = \"linear_elastic\"\n"
      "strength = \"lundborg\"\n"
      "rho0 = 2000.0\n"
      "young = 1e9\n"
      "poisson = 0.25\n"
      "cohesion = 1.0\n"
      "friction_intact = 0.6\n"
      "friction_damaged = 0.6\n"
      "strength_limit = 1e9\n"
      "tension_cutoff = 5.0\n");
  const auto msg = load_error(p);
  EXPECT_NE(msg.find(p.string() + ":12:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'tension_cutoff'"), std::string::npos) << msg;
}

TEST_F(CatalogueFile, MissingSourceIsAnError) {
  const auto p =
      write("[gas]\neos = \"ideal_gas\"\nstrength = \"hydro\"\nrho0 = 1.0\ngamma = 1.4\n");
  EXPECT_NE(load_error(p).find("'source'"), std::string::npos);
}

TEST_F(CatalogueFile, NonNumericParameter) {
  const auto p = write(
      "[gas]\nsource = \"t\"\neos = \"ideal_gas\"\nstrength = \"hydro\"\nrho0 = 1.0\n"
      "gamma = \"1.4\"\n");
  const auto msg = load_error(p);
  EXPECT_NE(msg.find(":6:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'gamma'"), std::string::npos) << msg;
}

TEST_F(CatalogueFile, SyntaxErrorHasLine) {
  const auto p = write("[gas]\nsource = \"t\"\neos = \n");
  EXPECT_NE(load_error(p).find(":3:"), std::string::npos) << load_error(p);
}

TEST_F(CatalogueFile, GoodFileLoads) {
  const auto p = write(
      "[gas]\nsource = \"t\"\neos = \"ideal_gas\"\nstrength = \"hydro\"\nrho0 = 1\ngamma = 1.4\n");
  const auto cat = MaterialCatalogue::load(p);
  EXPECT_EQ(cat.names(), std::vector<std::string>{"gas"});
  EXPECT_DOUBLE_EQ(cat.get("gas").get("rho0"), 1.0);  // integers are read as numbers
}

}  // namespace
}  // namespace shatter
