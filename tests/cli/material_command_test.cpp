// `shatter material` run as a user runs it: the built binary, its exit code, stdout and stderr.
// Numbers it prints are checked against the probe API (probe.hpp) the command wraps.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "shatter/material/catalogue.hpp"
#include "shatter/material/probe.hpp"

#ifndef SHATTER_BINARY
#error "SHATTER_BINARY must name the built shatter executable (tests/CMakeLists.txt)"
#endif

namespace shatter {
namespace {

struct Result {
  int code = -1;
  std::string out, err;
};

std::string slurp(const std::filesystem::path& p) {
  std::ifstream f(p);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

Result shatter_material(const std::vector<std::string>& args) {
  // ctest runs each test as its own process, several at once: a file name shared between them
  // let one test read another's output (seen once in CI-like runs), so the pid is in the name.
  const auto dir = std::filesystem::path(::testing::TempDir());
  const std::string tag = std::to_string(::getpid());
  const auto out = dir / ("shatter_material_stdout_" + tag + ".txt");
  const auto err = dir / ("shatter_material_stderr_" + tag + ".txt");
  std::string cmd = std::string("'") + SHATTER_BINARY + "' material";
  for (const auto& a : args) cmd += " '" + a + "'";
  cmd += " >'" + out.string() + "' 2>'" + err.string() + "'";
  const int status = std::system(cmd.c_str());
  Result r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

std::vector<std::vector<std::string>> csv_rows(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::string cell;
    std::istringstream ls(line);
    while (std::getline(ls, cell, ',')) cells.push_back(cell);
    rows.push_back(cells);
  }
  return rows;
}

constexpr int kBadInput = 2;  // src/cli/commands.hpp ExitCode

TEST(MaterialCommand, HugoniotCsvColumnsAndRowsEqualTheProbe) {
  const auto r = shatter_material({"aluminium_6061", "--up", "0,500,2000", "--csv"});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto rows = csv_rows(r.out);
  ASSERT_EQ(rows.size(), 4u) << r.out;
  EXPECT_EQ(r.out.substr(0, r.out.find('\n')),
            "up_m_per_s,us_m_per_s,p_Pa,rho_kg_per_m3,energy_J_per_kg");
  const auto spec = MaterialCatalogue::builtin().get("aluminium_6061");
  const double up[] = {0.0, 500.0, 2000.0};
  const auto expect = hugoniot(spec, up);
  for (std::size_t k = 0; k < 3; ++k) {
    ASSERT_EQ(rows[k + 1].size(), 5u);
    // The command prints %.17g, which round-trips a double exactly, and runs the same library
    // code: any difference at all means the command changed the numbers on the way.
    EXPECT_EQ(std::stod(rows[k + 1][0]), expect[k].up);
    EXPECT_EQ(std::stod(rows[k + 1][1]), expect[k].us);
    EXPECT_EQ(std::stod(rows[k + 1][2]), expect[k].p);
    EXPECT_EQ(std::stod(rows[k + 1][3]), expect[k].rho);
    EXPECT_EQ(std::stod(rows[k + 1][4]), expect[k].energy);
  }
  // The linear Us-up fit it was built from (Us = c0 + s up; 1e-9: bisection to adjacent doubles
  // in the compression, amplified by Us/up ~ 12).
  EXPECT_NEAR(std::stod(rows[2][1]), 5240.0 + 1.4 * 500.0, 1e-9 * 5940.0);
}

TEST(MaterialCommand, HugoniotRangeGivesEvenlySpacedRows) {
  const auto r = shatter_material({"basalt", "--hugoniot", "2000", "--points", "5", "--csv"});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto rows = csv_rows(r.out);
  ASSERT_EQ(rows.size(), 6u);
  for (int k = 0; k < 5; ++k) EXPECT_EQ(std::stod(rows[k + 1][0]), 500.0 * k);
  // Shocks compress and heat: p and rho rise along the table.
  for (int k = 2; k <= 5; ++k) {
    EXPECT_GT(std::stod(rows[k][2]), std::stod(rows[k - 1][2]));
    EXPECT_GT(std::stod(rows[k][3]), std::stod(rows[k - 1][3]));
  }
}

TEST(MaterialCommand, StatesCsvCoversEveryRhoWithEveryEnergy) {
  const auto r = shatter_material({"basalt", "--rho", "1500,2700,4000", "--energy", "0,3e7"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("region"), std::string::npos) << r.out;  // human table by default
  const auto c =
      shatter_material({"basalt", "--rho", "1500,2700,4000", "--energy", "0,3e7", "--csv"});
  ASSERT_EQ(c.code, 0) << c.err;
  const auto rows = csv_rows(c.out);
  ASSERT_EQ(rows.size(), 7u) << c.out;
  EXPECT_EQ(c.out.substr(0, c.out.find('\n')),
            "rho_kg_per_m3,energy_J_per_kg,p_Pa,c_bulk_m_per_s,c_p_m_per_s,region");
  const auto spec = MaterialCatalogue::builtin().get("basalt");
  std::size_t k = 1;
  for (double rho : {1500.0, 2700.0, 4000.0}) {
    for (double e : {0.0, 3e7}) {
      const auto s = probe_eos(spec, rho, e);
      ASSERT_EQ(rows[k].size(), 6u);
      EXPECT_EQ(std::stod(rows[k][0]), rho);
      EXPECT_EQ(std::stod(rows[k][1]), e);
      EXPECT_EQ(std::stod(rows[k][2]), s.pressure);  // exact: %.17g of the same computation
      EXPECT_EQ(std::stod(rows[k][3]), s.bulk_speed);
      EXPECT_EQ(std::stod(rows[k][4]), s.soundspeed);
      EXPECT_EQ(rows[k][5], s.region);
      ++k;
    }
  }
  // Regions of Eqs. 8-11 at these states (rho_iv = 2000, Eiv = 4.72, Ecv = 18.2 MJ/kg).
  EXPECT_EQ(rows[1][5], "vapour_expansion");  // rho < rho_iv, E < Eiv
  EXPECT_EQ(rows[2][5], "hot_expanded");      // E > Ecv
  EXPECT_EQ(rows[5][5], "compressed");
}

TEST(MaterialCommand, SweepIncludesBothEnds) {
  const auto r = shatter_material({"iron", "--rho-sweep", "7000:9000:5", "--csv"});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto rows = csv_rows(r.out);
  ASSERT_EQ(rows.size(), 6u);
  for (int k = 0; k < 5; ++k) EXPECT_EQ(std::stod(rows[k + 1][0]), 7000.0 + 500.0 * k);
}

TEST(MaterialCommand, ParameterOverrideReachesTheEos) {
  // Mie-Grüneisen: the acoustic limit (up = 0) of the Hugoniot is Us = c0 exactly (c^2 = c0^2 at
  // rho0, E = 0; one sqrt of a square: 1 ulp).
  const auto r = shatter_material({"aluminium_6061", "--param", "c0=6000", "--up", "0", "--csv"});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto rows = csv_rows(r.out);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_NEAR(std::stod(rows[1][1]), 6000.0, 1e-12 * 6000.0);
  const auto human = shatter_material({"aluminium_6061", "--param", "c0=6000"});
  EXPECT_NE(human.out.find("overridden"), std::string::npos) << human.out;
}

TEST(MaterialCommand, BadParameterOverridesAreRefused) {
  auto r = shatter_material({"basalt", "--param", "poisson=0.7"});
  EXPECT_EQ(r.code, kBadInput);
  EXPECT_NE(r.err.find("poisson"), std::string::npos) << r.err;
  r = shatter_material({"basalt", "--param", "no_such_key=1"});
  EXPECT_EQ(r.code, kBadInput);
  EXPECT_NE(r.err.find("no_such_key"), std::string::npos) << r.err;
  r = shatter_material({"basalt", "--param", "yield"});
  EXPECT_EQ(r.code, kBadInput);
  EXPECT_NE(r.err.find("KEY=VALUE"), std::string::npos) << r.err;
}

TEST(MaterialCommand, UnknownMaterialSuggestsTheNearestName) {
  auto r = shatter_material({"basalt_astroid"});
  EXPECT_EQ(r.code, kBadInput);
  EXPECT_NE(r.err.find("unknown material 'basalt_astroid'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("did you mean 'basalt_asteroid'?"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  r = shatter_material({"aluminum"});  // US spelling, and without the alloy number
  EXPECT_NE(r.err.find("did you mean 'aluminium_6061'?"), std::string::npos) << r.err;
  // Nothing close: no guess, but the known names are listed.
  r = shatter_material({"unobtainium"});
  EXPECT_EQ(r.code, kBadInput);
  EXPECT_EQ(r.err.find("did you mean"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("granite"), std::string::npos) << r.err;
}

TEST(MaterialCommand, NonPhysicalAndMalformedNumbersExitWithBadInput) {
  const std::vector<std::vector<std::string>> bad = {
      {"basalt", "--rho", "0"},
      {"basalt", "--rho", "-2700"},
      {"basalt", "--rho", "2700x"},
      {"basalt", "--rho", "2700,,3000"},
      {"basalt", "--energy", "nan"},
      {"basalt", "--rho-sweep", "1000:3000"},
      {"basalt", "--rho-sweep", "1000:3000:2.5"},
      {"basalt", "--up", "-100"},
      {"basalt", "--hugoniot", "0"},
      {"basalt", "--hugoniot", "fast"},
      {"basalt", "--hugoniot", "1000", "--points", "1"},
      {"basalt", "--ref-rho", "-1", "--up", "100"},
      {"basalt", "--rho", "2700", "--up", "100", "--csv"},  // two tables in one CSV
      {},                                                   // no material named
  };
  for (const auto& args : bad) {
    const auto r = shatter_material(args);
    std::string joined;
    for (const auto& a : args) joined += a + " ";
    EXPECT_EQ(r.code, kBadInput) << joined << "\n" << r.out << r.err;
    EXPECT_FALSE(r.err.empty()) << joined;  // a message, not a silent refusal
  }
  const auto r = shatter_material({"basalt", "--rho", "2700x"});
  EXPECT_NE(r.err.find("'2700x' is not a finite number"), std::string::npos) << r.err;
}

TEST(MaterialCommand, ListNamesEveryMaterialWithItsSource) {
  const auto r = shatter_material({"--list", "--csv"});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto cat = MaterialCatalogue::builtin();
  for (const auto& name : cat.names()) {
    const std::string row = name + "," + cat.get(name).eos + "," + cat.get(name).strength + ",\"";
    EXPECT_NE(r.out.find("\n" + row), std::string::npos) << name;
    EXPECT_NE(r.out.find(cat.get(name).source), std::string::npos) << name;
  }
  EXPECT_EQ(csv_rows(r.out).size(), cat.names().size() + 1);
}

TEST(MaterialCommand, OtherCatalogueFileIsLoadedAndValidated) {
  const auto dir = std::filesystem::path(::testing::TempDir());
  const auto good = dir / "cli_good_catalogue.toml";
  const auto bad = dir / "cli_bad_catalogue.toml";
  std::ofstream(good) << "[rock]\nsource = \"test\"\neos = \"linear_elastic\"\n"
                         "strength = \"hydro\"\nrho0 = 2000.0\nbulk_modulus = 8e9\n";
  std::ofstream(bad) << "[rock]\nsource = \"test\"\neos = \"linear_elastic\"\n"
                        "strength = \"hydro\"\nrho0 = -2000.0\nbulk_modulus = 8e9\n";
  auto r = shatter_material({"rock", "--catalogue", good.string(), "--up", "0", "--csv"});
  ASSERT_EQ(r.code, 0) << r.err;
  // Acoustic limit of a linear elastic EOS: Us = sqrt(K / rho0) = 2000 m/s (1e-12: one sqrt).
  EXPECT_NEAR(std::stod(csv_rows(r.out)[1][1]), 2000.0, 1e-12 * 2000.0);
  r = shatter_material({"rock", "--catalogue", bad.string()});
  EXPECT_EQ(r.code, kBadInput);
  EXPECT_NE(r.err.find("cli_bad_catalogue.toml:5"), std::string::npos) << r.err;  // file:line
  EXPECT_NE(r.err.find("rho0"), std::string::npos) << r.err;
}

TEST(MaterialCommand, OutWritesTheFileAndNothingToStdout) {
  const auto file = std::filesystem::path(::testing::TempDir()) / "al_hugoniot.csv";
  std::filesystem::remove(file);
  const auto r = shatter_material(
      {"aluminium_6061", "--hugoniot", "1000", "--points", "3", "--csv", "--out", file.string()});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_EQ(csv_rows(slurp(file)).size(), 4u);
}

}  // namespace
}  // namespace shatter

namespace shatter {
namespace {

// A porous material (issue 29): the summary names the compaction model and prints its crush
// curve; the Hugoniot from rest is the porous one (probe.hpp porous_hugoniot), starting at the
// bulk density rho0 / alpha0.
TEST(MaterialCommand, PorousMaterialPrintsCrushCurveAndPorousHugoniot) {
  const auto r = shatter_material({"porous_basalt"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("porosity eps_alpha"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("# crush curve (eps_alpha)"), std::string::npos) << r.out;
  const auto cat = MaterialCatalogue::builtin();
  const auto rows = crush_curve(cat.get("porous_basalt"), 21);
  char cell[32];
  for (std::size_t k : {std::size_t{0}, std::size_t{10}, std::size_t{20}}) {
    std::snprintf(cell, sizeof cell, " %.6f ", rows[k].alpha);  // the table's alpha column
    EXPECT_NE(r.out.find(cell), std::string::npos) << cell << "\n" << r.out;
  }

  const auto h = shatter_material({"porous_basalt", "--up", "500", "--csv"});
  ASSERT_EQ(h.code, 0) << h.err;
  const auto csv = csv_rows(h.out);
  ASSERT_EQ(csv.size(), 2u);
  const double up[] = {500.0};
  const auto want = porous_hugoniot(cat.get("porous_basalt"), up).front();
  EXPECT_NEAR(std::stod(csv[1][2]), want.p, 1e-9 * want.p);  // printed with 17 digits
  const auto human = shatter_material({"porous_basalt", "--up", "500"});
  EXPECT_NE(human.out.find("porous Hugoniot (eps_alpha) from rho = 2160"), std::string::npos)
      << human.out;
}

// The summary of a porous catalogue entry also gives its porous Hugoniot from rest (at 100, 300,
// 1000 and 3000 m/s), the rows equal to the probe's as the table prints them (%.6e pressure).
TEST(MaterialCommand, PorousSummaryIncludesThePorousHugoniot) {
  const auto r = shatter_material({"pumice"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("# crush curve (p_alpha)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("# porous Hugoniot (p_alpha) from rho = 581.897"), std::string::npos)
      << r.out;
  const auto cat = MaterialCatalogue::builtin();
  const double up[] = {100.0, 300.0, 1000.0, 3000.0};
  char cell[32];
  for (const auto& row : porous_hugoniot(cat.get("pumice"), up)) {
    std::snprintf(cell, sizeof cell, " %.6e ", row.p);
    EXPECT_NE(r.out.find(cell), std::string::npos) << cell << "\n" << r.out;
  }
  // Dense materials keep their summary without a Hugoniot.
  EXPECT_EQ(shatter_material({"basalt"}).out.find("Hugoniot"), std::string::npos);
}

}  // namespace
}  // namespace shatter
