// End-to-end smoke test of the `shatter` program on a coarse laboratory impact (Nakamura &
// Fujiwara 1991, scenes/lab-impact-coarse.toml at 4 mm cells: about 7 000 points, 4 us): the run
// finishes, writes snapshots, the XDMF series, the time series and a checkpoint; the energy
// error stays bounded; resume extends the run; bad input exits non-zero without output.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "shatter/io/checkpoint.hpp"
#include "shatter/io/snapshot.hpp"

namespace {

namespace fs = std::filesystem;

// The program is built next to the test programs' folder: build/shatter, build/tests/validation.
fs::path shatter_program() {
  return fs::read_symlink("/proc/self/exe").parent_path().parent_path() / "shatter";
}

int run(const std::string& args) {
  const std::string cmd = shatter_program().string() + " " + args + " > /dev/null 2>&1";
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto pos = text.find(what); pos != std::string::npos; pos = text.find(what, pos + 1)) ++n;
  return n;
}

class LabImpactSmoke : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(fs::exists(shatter_program()))
        << "build the 'shatter' target first: " << shatter_program();
    dir_ = fs::temp_directory_path() / ("shatter_smoke_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string scene() const {
    return std::string(SHATTER_SOURCE_DIR) + "/scenes/lab-impact-coarse.toml";
  }
  fs::path dir_;
};

const std::string kCoarse =
    " --set solver.cell_size=4.0e-3 --set output.snapshot_every=1.0e-6"
    " --set output.checkpoint_every=2.0e-6 --threads 2 --quiet";

TEST_F(LabImpactSmoke, RunWritesSnapshotsSeriesAndCheckpointWithBoundedEnergyError) {
  const fs::path out = dir_ / "run";
  ASSERT_EQ(
      run("run " + scene() + " --out " + out.string() + kCoarse + " --set solver.end_time=4.0e-6"),
      0);

  // Snapshots at 0, 1, 2, 3, 4 us, each with the damage column, and all in the XDMF series.
  for (int k = 0; k <= 4; ++k) {
    const auto file = out / "snapshots" / ("snapshot_00000" + std::to_string(k) + ".h5");
    ASSERT_TRUE(fs::exists(file)) << file;
    const auto info = shatter::io::inspect_snapshot(file);
    EXPECT_NEAR(info.header.time, 1.0e-6 * k, 1e-18);
    EXPECT_EQ(info.header.symmetry_axis, 2);
    EXPECT_GT(info.particles, 5000u);
  }
  const std::string xmf = slurp(out / "particles.xmf");
  EXPECT_EQ(count(xmf, "<Time Value="), 5u);
  EXPECT_EQ(count(xmf, "<Attribute Name=\"damage\""), 5u);

  // Time series: a header with units and rows whose energy error stays bounded. The paper keeps
  // it below 0.6 % at its resolution; 2 % leaves room for this very coarse grid.
  std::ifstream ts(out / "timeseries.csv");
  std::string line;
  std::getline(ts, line);
  EXPECT_NE(line.find("energy_error"), std::string::npos);
  EXPECT_NE(line.find("time_s"), std::string::npos);
  int rows = 0;
  double worst = 0.0, last_failure = 0.0;
  while (std::getline(ts, line)) {
    std::vector<std::string> f;
    std::stringstream ls(line);
    for (std::string v; std::getline(ls, v, ',');) f.push_back(v);
    ASSERT_EQ(f.size(), 18u) << line;
    worst = std::max(worst, std::abs(std::stod(f[9])));
    last_failure = std::stod(f[13]);
    // The unresolved share of the kinetic energy (issue 16) is a fraction by Cauchy-Schwarz;
    // after the impact it is tens of percent, far from round-off (its row at t = 0 is 0).
    const double unresolved = std::stod(f[15]);
    EXPECT_GE(unresolved, 0.0) << line;
    EXPECT_LE(unresolved, 1.0) << line;
    ++rows;
  }
  EXPECT_GT(rows, 3);
  EXPECT_LT(worst, 0.02);
  EXPECT_GE(last_failure, 0.0);
  EXPECT_LE(last_failure, 1.0);

  const auto c = shatter::io::read_checkpoint(out / "checkpoint.h5");
  EXPECT_EQ(c.state.clock.time, 4.0e-6);
  EXPECT_NE(c.state.scene_text.find("[body.target.damage]"), std::string::npos);
  EXPECT_EQ(slurp(out / "scene.toml").rfind("# Resolved by shatter", 0), 0u);
  EXPECT_TRUE(fs::exists(out / "fragments.csv"));

  // Resume continues the same run directory to a later end time.
  ASSERT_EQ(run("resume " + (out / "checkpoint.h5").string() +
                " --set solver.end_time=5.0e-6 --quiet --threads 1"),
            0);
  EXPECT_TRUE(fs::exists(out / "snapshots" / "snapshot_000005.h5"));
  EXPECT_EQ(count(slurp(out / "particles.xmf"), "<Time Value="), 6u);
  EXPECT_EQ(shatter::io::read_checkpoint(out / "checkpoint.h5").state.clock.time, 5.0e-6);
}

TEST_F(LabImpactSmoke, BadInputExitsNonZeroAndWritesNothing) {
  EXPECT_EQ(run("run /nonexistent/scene.toml --out " + (dir_ / "a").string()), 2);
  EXPECT_FALSE(fs::exists(dir_ / "a"));
  EXPECT_EQ(run("run " + scene() + " --out " + (dir_ / "b").string() + " --set solver.cfl=2"), 2);
  EXPECT_FALSE(fs::exists(dir_ / "b"));
  EXPECT_EQ(
      run("run " + scene() + " --out " + (dir_ / "c").string() + " --set body.target.radus=1"), 2);
  EXPECT_FALSE(fs::exists(dir_ / "c"));
  EXPECT_EQ(run("resume " + (dir_ / "missing.h5").string()), 2);
  EXPECT_EQ(run("fragments " + (dir_ / "missing.h5").string()), 2);
}

TEST_F(LabImpactSmoke, VersionIsPrinted) {
  EXPECT_EQ(run("--version"), 0);
}

}  // namespace
