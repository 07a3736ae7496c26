// [solver.mpi] (issue 28): the MPI load-balancing values, once read from the environment, are
// scene keys with the same defaults, written into the run's scene copy; a malformed value is
// refused naming the key and its line.

#include <gtest/gtest.h>

#include "scene_fixture.hpp"

namespace shatter::scene {
namespace {

using test::error_of;
using test::expect_names;
using test::kTinyScene;
using test::line_of;
using test::parse;
using test::with;

// The [solver.mpi] table after the [solver] lines of the tiny scene.
std::string with_mpi(const std::string& lines) {
  return with("[domain]", "[solver.mpi]\n" + lines + "\n\n[domain]");
}

TEST(MpiKeys, DefaultsAreTheOldEnvironmentDefaultsAndAreRecorded) {
  const Scene s = parse(kTinyScene);
  EXPECT_EQ(s.solver.mpi.rebalance_every, 10U);
  EXPECT_EQ(s.solver.mpi.imbalance, 1.2);
  EXPECT_NE(s.resolved.find("[solver.mpi]"), std::string::npos) << s.resolved;
  EXPECT_NE(s.resolved.find("rebalance_every = 10"), std::string::npos) << s.resolved;
  EXPECT_NE(s.resolved.find("imbalance = 1.2"), std::string::npos) << s.resolved;
}

TEST(MpiKeys, GivenValuesAreTakenFromTheTableAndFromSet) {
  const Scene s = parse(with_mpi("rebalance_every = 1\nimbalance = 1.0"));
  EXPECT_EQ(s.solver.mpi.rebalance_every, 1U);
  EXPECT_EQ(s.solver.mpi.imbalance, 1.0);
  const Scene t = parse(kTinyScene, {"solver.mpi.imbalance=1.5"});
  EXPECT_EQ(t.solver.mpi.imbalance, 1.5);
}

TEST(MpiKeys, MalformedValuesNameTheKeyAndLine) {
  for (const std::string& lines :
       {std::string("rebalance_every = 0"), std::string("rebalance_every = 2.5"),
        std::string("rebalance_every = \"often\"")}) {
    const std::string text = with_mpi(lines);
    expect_names(error_of(text), line_of(text, "rebalance_every"), "solver.mpi.rebalance_every");
  }
  for (const std::string& lines : {std::string("imbalance = 0.5"), std::string("imbalance = nan"),
                                   std::string("imbalance = \"1.2x\"")}) {
    const std::string text = with_mpi(lines);
    expect_names(error_of(text), line_of(text, "imbalance"), "solver.mpi.imbalance");
  }
  const std::string unknown = with_mpi("imbalence = 1.5");
  expect_names(error_of(unknown), line_of(unknown, "imbalence"), "solver.mpi.imbalence");
}

TEST(MpiKeys, RefusedWithSph) {
  const std::string text = with_mpi("imbalance = 1.5");
  const std::string msg = error_of(text, {"solver.method=\"sph\""});
  EXPECT_NE(msg.find("solver.mpi"), std::string::npos) << msg;
}

}  // namespace
}  // namespace shatter::scene
