// `shatter check`, the run's memory guard and the command line's handling of mistakes and
// signals (issue 13 items 5 and 7), run as a user runs them on tests/fuzz/tiny.toml.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "support/cli_run.hpp"

namespace shatter {
namespace {

namespace fs = std::filesystem;
using test::kTiny;
using test::slurp;

struct Result {
  int code = -1;
  std::string out, err;
};

class Cli : public test::TempDirTest {
 protected:
  Cli() : TempDirTest("check") {}

  Result shatter(const std::vector<std::string>& args, const std::string& env = "") const {
    std::string cmd = env + " " + test::shatter_command(args);
    cmd += " 2>'" + (dir_ / "stderr.txt").string() + "' >'" + (dir_ / "stdout.txt").string() + "'";
    const int status = std::system(cmd.c_str());
    return {test::exit_code(status), slurp(dir_ / "stdout.txt"), slurp(dir_ / "stderr.txt")};
  }
};

// The number after `body NAME:` ... `N points` in run --check's log, or in check's table.
long points_in(const std::string& text, const std::string& pattern) {
  std::smatch m;
  if (!std::regex_search(text, m, std::regex(pattern))) return -1;
  return std::stol(m[1]);
}

TEST_F(Cli, CheckPrintsPointsMemoryStepsAndRunTimeAndAgreesWithTheRun) {
  const Result c = shatter({"check", kTiny.string(), "--threads", "1"});
  ASSERT_EQ(c.code, 0) << c.err;
  for (const char* what : {"memory: ~", "time step: ", "steps", "run time: ~", "half model"}) {
    EXPECT_NE(c.out.find(what), std::string::npos) << what << " missing in\n" << c.out;
  }
  // The counts come from counting the lattice without storing it; they must be those of the
  // points `run` creates (the same inside test on the same lattice): exact equality.
  const Result r = shatter({"run", kTiny.string(), "--check", "--threads", "1"});
  ASSERT_EQ(r.code, 0) << r.err;
  for (const std::string body : {"projectile", "target"}) {
    const long checked = points_in(c.out, body + R"(\s+(\d+)\s)");
    const long run = points_in(r.err, "body " + body + R"(:.*?, (\d+) points)");
    EXPECT_GT(checked, 0) << c.out;
    EXPECT_EQ(checked, run) << body;
  }
  EXPECT_FALSE(fs::exists(dir_ / "out")) << "check must write nothing";
}

// Which catalogue a run reads is in its log: a copied binary uses the catalogue it was built or
// installed with, and a scene's `catalogue = "..."` replaces it (issue 34).
TEST_F(Cli, RunLogNamesTheMaterialCatalogueFile) {
  const Result r = shatter({"run", kTiny.string(), "--check", "--threads", "1"});
  ASSERT_EQ(r.code, 0) << r.err;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.err, m, std::regex(R"(materials from (\S+))"))) << r.err;
  EXPECT_TRUE(fs::is_regular_file(m[1].str())) << m[1];
  EXPECT_EQ(fs::path(m[1].str()).filename(), "materials.toml");
}

TEST_F(Cli, RunRefusesASceneLargerThanTheMachineBeforeCreatingItsPoints) {
  // cell 40 um: ~2.7e8 points, ~440 GiB by the estimate (measured 1727 B per point), more than
  // any machine this runs on. Filling it would take minutes and then std::bad_alloc.
  const fs::path out = dir_ / "huge";
  const Result r = shatter({"run", kTiny.string(), "--set", "solver.cell_size=4e-5", "--out",
                            out.string(), "--threads", "1"});
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("the scene needs about"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("GiB"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("2.73e+08 points"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out)) << "nothing may be written for a refused run";
  // `check` reports the same scene (from the volumes, without counting 2.7e8 points) and
  // refuses it too.
  const Result c = shatter({"check", kTiny.string(), "--set", "solver.cell_size=4e-5"});
  EXPECT_EQ(c.code, 2);
  EXPECT_NE(c.out.find("~2.73e+08"), std::string::npos) << c.out;
}

TEST_F(Cli, CheckRefusesFlawParametersTheRunWouldRefuse) {
  // 2112 target points x 2 (the half model draws for both halves) need >= 4224 flaws.
  const Result few = shatter({"check", kTiny.string(), "--set", "body.target.damage.weibull_m=3.0",
                              "--set", "body.target.damage.total_flaws=4000"});
  EXPECT_EQ(few.code, 2) << few.out;
  EXPECT_NE(few.err.find("body.target.damage.total_flaws: = 4000 is below the body's 4224 points"),
            std::string::npos)
      << few.err;
  // n_tot must exceed 10^m (MPM paper Sec. 3.3), checked by drawing the flaws of one point.
  const Result low =
      shatter({"check", kTiny.string(), "--set", "body.target.damage.weibull_m=12.0"});
  EXPECT_EQ(low.code, 2) << low.out;
  EXPECT_NE(low.err.find("total_flaws > 10^m"), std::string::npos) << low.err;
}

TEST_F(Cli, MemoryLimitFromTheEnvironmentIsHonoured) {
  const Result r =
      shatter({"run", kTiny.string(), "--out", (dir_ / "o").string()}, "SHATTER_MEMORY_LIMIT=1e6");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("977 KiB of memory is available"), std::string::npos) << r.err;
}

TEST_F(Cli, MisspeltCommandSuggestsTheNearest) {
  for (const auto& [typo, meant] :
       {std::pair{"rnu", "run"}, std::pair{"chekc", "check"}, std::pair{"resum", "resume"},
        std::pair{"fragmnets", "fragments"}}) {
    const Result r = shatter({typo, kTiny.string()});
    EXPECT_EQ(r.code, 2) << typo;
    EXPECT_NE(r.err.find(std::string("did you mean '") + meant + "'"), std::string::npos) << r.err;
  }
}

TEST_F(Cli, DirectoryGivenAsSceneOrCheckpointGetsItsOwnMessage) {
  for (const char* cmd : {"run", "check"}) {
    const Result r = shatter({cmd, dir_.string()});
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("is a directory, not a scene file"), std::string::npos) << r.err;
  }
  const Result r = shatter({"resume", dir_.string()});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("is a directory, not a checkpoint"), std::string::npos) << r.err;
}

TEST_F(Cli, UnusableOutNamesTheOption) {
  // A file where the directory should be, and a place below a file.
  const Result file = shatter({"run", kTiny.string(), "--out", kTiny.string()});
  EXPECT_EQ(file.code, 2);
  EXPECT_NE(file.err.find("--out " + kTiny.string() + ": exists and is not a directory"),
            std::string::npos)
      << file.err;
  const Result below = shatter({"run", kTiny.string(), "--out", (kTiny / "run").string()});
  EXPECT_EQ(below.code, 2);
  EXPECT_NE(below.err.find("--out"), std::string::npos) << below.err;
  EXPECT_NE(below.err.find("is not a directory"), std::string::npos) << below.err;
}

TEST_F(Cli, AbsurdNumbersAreEchoedReadably) {
  // Each is refused; no message may spell a number out in more than 17 significant digits
  // (the round-trip precision of a double).
  const std::vector<std::vector<std::string>> cases = {
      {"run", kTiny.string(), "--set", "solver.cell_size=1e-300"},
      {"run", kTiny.string(), "--set", "body.target.velocity=[1e300,0,0]"},
      {"run", kTiny.string(), "--set", "fracture.threshold=1e300"},
      {"run", kTiny.string(), "--set", "body.target.material.rho0=1e300"},
      {"run", kTiny.string(), "--set", "domain.hi=[1e300,1e300,1e300]"},
      {"run", kTiny.string(), "--threads", "1e300"},
      {"check", kTiny.string(), "--set", "solver.end_time=1e300"}};
  for (const auto& args : cases) {
    const Result r = shatter(args);
    EXPECT_EQ(r.code, 2) << args[3] << "\n" << r.err;
    EXPECT_FALSE(std::regex_search(r.err, std::regex(R"(\d{18})"))) << r.err;
  }
}

TEST_F(Cli, SigtermWritesACheckpointSaysHowToResumeAndExitsNonZero) {
  const fs::path out = dir_ / "run";
  const fs::path err = dir_ / "run.err";
  // An end time the tiny scene takes minutes to reach; the signal comes once it has stepped.
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    std::freopen(err.c_str(), "w", stderr);
    std::freopen("/dev/null", "w", stdout);
    ::execl(SHATTER_BINARY, SHATTER_BINARY, "run", kTiny.c_str(), "--out", out.c_str(), "--threads",
            "1", "--set", "solver.end_time=1e-3", "--set", "output.checkpoint_every=0",
            static_cast<char*>(nullptr));
    std::_Exit(127);
  }
  // timeseries.csv gets a row per step (timeseries_every = 1): wait for a few steps.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  auto rows = [&] {
    const std::string t = slurp(out / "timeseries.csv");
    return std::count(t.begin(), t.end(), '\n');
  };
  while (rows() < 4 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_EQ(::kill(child, SIGTERM), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status)) << "killed instead of stopping: " << slurp(err);
  EXPECT_EQ(WEXITSTATUS(status), 128 + SIGTERM);
  const std::string log = slurp(err);
  const fs::path cp = out / "checkpoint.h5";
  EXPECT_NE(log.find("SIGTERM received"), std::string::npos) << log;
  EXPECT_NE(log.find("continue with: shatter resume " + cp.string()), std::string::npos) << log;
  ASSERT_TRUE(fs::exists(cp)) << log;

  // The checkpoint continues: resume it to a little after the time it was written at.
  std::smatch m;
  ASSERT_TRUE(std::regex_search(log, m, std::regex(R"(stopped at t = (\S+) s)"))) << log;
  const double t = std::stod(m[1]);
  EXPECT_GT(t, 0.0);
  std::ostringstream end;
  end.precision(17);
  end << "solver.end_time=" << t + 1e-7;
  const Result r = shatter({"resume", cp.string(), "--threads", "1", "--set", end.str()});
  EXPECT_EQ(r.code, 0) << r.err;
}

}  // namespace
}  // namespace shatter
