// `shatter check SCENE --stages`: the step's stage list as the scene builds it (issue 28), run as
// a user runs it on tests/fuzz/tiny.toml. Golden lists: a change to the step's shape
// (src/mpm/step.cpp) or to what the command prints must show here.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "support/cli_run.hpp"

namespace shatter {
namespace {

namespace fs = std::filesystem;
using test::kTiny;

struct Listed {
  int code = -1;
  std::string out;
  std::vector<std::string> stages;  // the names of the numbered lines, in order
};

// `prefix` runs the command under a launcher (mpiexec); stderr is dropped (the log).
Listed stages_of(const std::vector<std::string>& sets, const std::string& prefix = "") {
  const fs::path out = fs::temp_directory_path() / ("shatter_stages_" + std::to_string(::getpid()));
  std::string cmd =
      prefix + " " +
      test::shatter_command({"check", kTiny.string(), "--stages", "--threads", "1", "--quiet"});
  for (const auto& s : sets) cmd += " --set '" + s + "'";
  cmd += " 2>/dev/null >'" + out.string() + "'";
  const int status = std::system(cmd.c_str());
  Listed l;
  l.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  l.out = test::slurp(out);
  fs::remove(out);
  const std::regex line(R"(^\s*\d+\. (\S+))");
  std::istringstream lines(l.out);
  for (std::string s; std::getline(lines, s);) {
    std::smatch m;
    if (std::regex_search(s, m, line)) l.stages.push_back(m[1]);
  }
  return l;
}

using Names = std::vector<std::string>;

TEST(CheckStages, FlipWithOutflowFacesIsTheMuslStep) {
  // tiny.toml: FLIP (the default), single-field contact, outflow faces.
  const Listed l = stages_of({});
  ASSERT_EQ(l.code, 0) << l.out;
  EXPECT_EQ(l.stages,
            (Names{"sort", "p2g", "grid_update", "g2p", "remap", "remap_velocity", "constitutive",
                   "advance_positions", "outflow", "energy", "time_step"}))
      << l.out;
  EXPECT_NE(l.out.find("on 1 rank, 11 stages"), std::string::npos) << l.out;
  EXPECT_NE(l.out.find("grid_update  (contact: single_field)"), std::string::npos) << l.out;
  EXPECT_NE(l.out.find("memory: ~"), std::string::npos) << "the check's estimate comes first";
}

TEST(CheckStages, XpicFiltersBeforeG2pAndKeepsTheRemap) {
  const Listed l = stages_of({"solver.transfer=\"xpic\"", "solver.xpic_order=2"});
  ASSERT_EQ(l.code, 0) << l.out;
  EXPECT_EQ(l.stages, (Names{"sort", "p2g", "grid_update", "xpic", "xpic_nodes", "g2p", "remap",
                             "remap_velocity", "constitutive", "advance_positions", "outflow",
                             "energy", "time_step"}))
      << l.out;
  EXPECT_NE(l.out.find("xpic  (transfer: xpic)"), std::string::npos) << l.out;
}

TEST(CheckStages, MultiFieldContactRunsInsideGridUpdate) {
  const Listed l = stages_of({"solver.contact=\"multi_field\""});
  ASSERT_EQ(l.code, 0) << l.out;
  EXPECT_EQ(l.stages, stages_of({}).stages) << "contact adds no stage of its own";
  EXPECT_NE(l.out.find("grid_update  (contact: multi_field)"), std::string::npos) << l.out;
}

TEST(CheckStages, SphListsItsFixedStep) {
  const Listed l = stages_of({"solver.method=\"sph\""});
  ASSERT_EQ(l.code, 0) << l.out;
  EXPECT_EQ(l.stages, (Names{"kick", "rates", "material", "drift", "search", "forces", "energy"}))
      << l.out;
  EXPECT_NE(l.out.find("step is fixed"), std::string::npos) << l.out;
}

#ifdef SHATTER_MPIEXEC
// The leak check is off under mpiexec, as for tests/mpi (its CMakeLists says why: OpenMPI's
// unloaded plugins show as leaks from "<unknown module>"); ignored without ASan.
Listed stages_on_two_ranks(const std::vector<std::string>& sets) {
  return stages_of(sets, std::string("OMPI_ALLOW_RUN_AS_ROOT=1 "
                                     "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
                                     "ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 '") +
                             SHATTER_MPIEXEC + "' --oversubscribe -np 2");
}

TEST(CheckStages, TwoRanksAddTheMigrationAndAHaloExchangeAfterEachScatter) {
  const Listed l = stages_on_two_ranks({});
  ASSERT_EQ(l.code, 0) << l.out;
  EXPECT_EQ(l.stages, (Names{"migrate", "sort", "p2g", "halo", "grid_update", "g2p", "remap",
                             "halo_remap", "remap_velocity", "constitutive", "advance_positions",
                             "outflow", "energy", "time_step"}))
      << "rank 0 alone prints:\n"
      << l.out;
  EXPECT_NE(l.out.find("on 2 ranks, 14 stages"), std::string::npos) << l.out;
}

TEST(CheckStages, TwoRanksExchangeAfterEachFilterPass) {
  const Listed l = stages_on_two_ranks({"solver.transfer=\"xpic\"", "solver.xpic_order=3"});
  ASSERT_EQ(l.code, 0) << l.out;
  EXPECT_EQ(l.stages, (Names{"migrate",
                             "sort",
                             "p2g",
                             "halo",
                             "grid_update",
                             "xpic",
                             "halo_xpic",
                             "xpic_nodes",
                             "xpic",
                             "halo_xpic",
                             "xpic_nodes",
                             "g2p",
                             "remap",
                             "halo_remap",
                             "remap_velocity",
                             "constitutive",
                             "advance_positions",
                             "outflow",
                             "energy",
                             "time_step"}))
      << "rank 0 alone prints:\n"
      << l.out;
}
#endif

}  // namespace
}  // namespace shatter
