// `shatter check`'s resolution advice (issue 31, item 4), in 3-D and in r-z: cells and points per
// projectile radius, and the warnings below 10 CPPR and for a body smaller than two cells.

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <regex>
#include <string>
#include <vector>

#include "support/cli_run.hpp"

namespace shatter {
namespace {

namespace fs = std::filesystem;

const fs::path kRz =
    fs::path(SHATTER_SOURCE_DIR) / "scenes" / "examples" / "axisymmetric-head-on.toml";

class Advice : public test::TempDirTest {
 protected:
  Advice() : TempDirTest("advice") {}

  std::string check(const fs::path& scene, const std::vector<std::string>& sets = {}) const {
    std::vector<std::string> args = {"check", scene.string(), "--threads", "1"};
    for (const auto& s : sets) args.insert(args.end(), {"--set", s});
    const std::string cmd = test::shatter_command(args) + " >'" + (dir_ / "out.txt").string() +
                            "' 2>'" + (dir_ / "err.txt").string() + "'";
    EXPECT_EQ(test::exit_code(std::system(cmd.c_str())), 0) << test::slurp(dir_ / "err.txt");
    return test::slurp(dir_ / "out.txt");
  }
};

// tiny.toml: a 3.5 mm projectile in 2 mm cells, 1.75 CPPR: the warning, in 3-D.
TEST_F(Advice, ThreeDimensionalSceneGetsCpprAndTheWarning) {
  const std::string out = check(test::kTiny);
  EXPECT_NE(out.find("resolution (3-D)"), std::string::npos) << out;
  EXPECT_NE(out.find("projectile       radius 0.0035 m: 1.75 CPPR, 3.5 points per radius"),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("warning: the projectile 'projectile' has 1.75 cells per radius, below 10"),
            std::string::npos)
      << out;
}

// The r-z example at 8.75 CPPR warns; at 0.2 mm (17.5 CPPR) it only notes the crater advice; at
// 4 mm the projectile is smaller than two cells.
TEST_F(Advice, AxisymmetricSceneGetsCpprAndTheThresholds) {
  const std::string out = check(kRz);
  EXPECT_NE(out.find("axisymmetric (r-z)"), std::string::npos) << out;
  EXPECT_NE(out.find("resolution (axisymmetric r-z)"), std::string::npos) << out;
  EXPECT_NE(out.find("8.75 CPPR"), std::string::npos) << out;
  EXPECT_NE(out.find("warning: the projectile"), std::string::npos) << out;
  const std::string fine = check(kRz, {"solver.cell_size=0.2e-3"});
  EXPECT_EQ(fine.find("warning"), std::string::npos) << fine;
  EXPECT_NE(fine.find("note: the projectile 'projectile' has 17.5 CPPR"), std::string::npos)
      << fine;
  const std::string coarse = check(kRz, {"solver.cell_size=4e-3"});
  EXPECT_NE(coarse.find("warning: body 'projectile' (radius 0.0035 m) is smaller than two cells"),
            std::string::npos)
      << coarse;
}

}  // namespace
}  // namespace shatter
