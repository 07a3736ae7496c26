// Scene errors of issue 14: misleading messages fixed (items 5) and physical ranges (item 2).
// Each test checks that the message names the file (and line) and the key actually at fault, and
// for a range, the range and its reason.

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "scene_fixture.hpp"

namespace shatter::scene {
namespace {

using test::error_of;
using test::expect_names;
using test::kTinyScene;
using test::line_of;
using test::with;

std::filesystem::path scratch(const std::string& name) {
  const auto d = std::filesystem::temp_directory_path() /
                 ("shatter_reliability_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

std::string load_error(const std::filesystem::path& file) {
  try {
    load_scene(file);
  } catch (const SceneError& e) {
    return e.what();
  }
  ADD_FAILURE() << file << " was accepted";
  return {};
}

TEST(ReliabilityErrors, DirectoryAsSceneIsNamedAsADirectory) {
  // Was: "solver: is required but missing" (an ifstream opens a directory as an empty file).
  const auto d = scratch("dir");
  const std::string msg = load_error(d);
  EXPECT_NE(msg.find("is a directory, not a scene file"), std::string::npos) << msg;
  EXPECT_EQ(msg.find("solver"), std::string::npos) << msg;
  std::filesystem::remove_all(d);
}

TEST(ReliabilityErrors, FifoAsSceneIsRefusedWithoutBlocking) {
  // Reading a FIFO with no writer would block forever.
  const auto d = scratch("fifo");
  ASSERT_EQ(::mkfifo((d / "pipe.toml").c_str(), 0600), 0);
  EXPECT_NE(load_error(d / "pipe.toml").find("not a regular file"), std::string::npos);
  std::filesystem::remove_all(d);
}

TEST(ReliabilityErrors, MissingCatalogueFileNamesTheCatalogueKey) {
  // Was: "catalogue: /path/nofile.toml:0: TOML syntax error: File could not be opened".
  const std::string text = "catalogue = \"no_such_catalogue.toml\"\n" + kTinyScene;
  const std::string msg = error_of(text);
  expect_names(msg, 1, "catalogue");
  EXPECT_NE(msg.find("no such catalogue file"), std::string::npos) << msg;
  EXPECT_EQ(msg.find("syntax"), std::string::npos) << msg;
}

TEST(ReliabilityErrors, MissingExtendsFileNamesTheExtendsKey) {
  const std::string text = "extends = \"no_such_base.toml\"\n" + kTinyScene;
  const std::string msg = error_of(text);
  expect_names(msg, 1, "extends");
  EXPECT_NE(msg.find("no such file"), std::string::npos) << msg;
}

TEST(ReliabilityErrors, UnknownProjectileNameNamesTheImpactKey) {
  // Was: "body.projectile.centre: is required but missing".
  const std::string text = with("projectile = \"projectile\"", "projectile = \"projectil\"");
  const std::string msg = error_of(text);
  expect_names(msg, line_of(text, "projectile = \"projectil\""), "impact.projectile");
  EXPECT_NE(msg.find("did you mean 'projectile'"), std::string::npos) << msg;
  EXPECT_EQ(msg.find("centre"), std::string::npos) << msg;
}

TEST(ReliabilityErrors, UnknownTargetNameNamesTheImpactKey) {
  const std::string text = with("target = \"target\"", "target = \"targte\"");
  expect_names(error_of(text), line_of(text, "target = \"targte\""), "impact.target");
}

TEST(ReliabilityErrors, ImpactSpeedBeyondTheRangeStatesRangeAndReason) {
  // The run that never ended: 1/2 v^2 overflowed to infinity.
  const std::string text = with("speed = 3200.0", "speed = 1.0e200");
  const std::string msg = error_of(text);
  expect_names(msg, line_of(text, "speed = 1.0e200"), "impact.speed");
  EXPECT_NE(msg.find("[0, 1e+06] m/s"), std::string::npos) << msg;
  EXPECT_NE(msg.find("0.3% of c"), std::string::npos) << msg;
}

TEST(ReliabilityErrors, TensOfKilometresPerSecondAreAccepted) {
  EXPECT_NO_THROW(test::parse(with("speed = 3200.0", "speed = 70.0e3")));
}

TEST(ReliabilityErrors, BodyVelocityBeyondTheRangeIsRefused) {
  const std::string text =
      with("material = \"basalt\"", "material = \"basalt\"\nvelocity = [0.0, 2.0e6, 0.0]");
  expect_names(error_of(text), line_of(text, "velocity = [0.0, 2.0e6"), "body.target.velocity");
}

TEST(ReliabilityErrors, SpacingGivingTooManyPointsIsRefusedBeforeFilling) {
  // 4e12 points: filling would take hours and all memory before any message.
  const std::string text = with("radius = 0.01", "radius = 0.01\nspacing = 1.0e-6");
  const std::string msg = error_of(text);
  expect_names(msg, line_of(text, "spacing = 1.0e-6"), "body.target.spacing");
  EXPECT_NE(msg.find("points"), std::string::npos) << msg;
}

TEST(ReliabilityErrors, CellSizeBelowTheContinuumIsRefused) {
  const std::string text = with("cell_size = 2.0e-3", "cell_size = 1.0e-300");
  expect_names(error_of(text), line_of(text, "cell_size = 1.0e-300"), "solver.cell_size");
}

TEST(ReliabilityErrors, SnapshotCadenceWritingMillionsOfFilesIsRefused) {
  const std::string text = with("snapshot_every = 0.5e-6", "snapshot_every = 1.0e-15");
  expect_names(error_of(text), line_of(text, "snapshot_every = 1.0e-15"), "output.snapshot_every");
}

TEST(ReliabilityErrors, ModulusBeyondDiamondIsRefusedWithItsReason) {
  const std::string msg = error_of(kTinyScene, {"body.target.material.young=1e20"});
  EXPECT_NE(msg.find("body.target.material.young"), std::string::npos) << msg;
  EXPECT_NE(msg.find("diamond"), std::string::npos) << msg;
}

TEST(ReliabilityErrors, IceAndWeakRegolithAreAccepted) {
  // Ice: Young's modulus ~9 GPa; weak regolith: a yield stress of 10 Pa.
  EXPECT_NO_THROW(
      test::parse(kTinyScene, {"body.target.material.young=9e9", "body.target.material.yield=10"}));
}

TEST(ReliabilityErrors, MisspeltDamageModelKeySuggestsModel) {
  // Was: "body.target.damage.mdoel: must be a number (got a string)".
  const std::string text = with("model = \"grady_kipp\"", "mdoel = \"grady_kipp\"");
  const std::string msg = error_of(text);
  expect_names(msg, line_of(text, "mdoel"), "body.target.damage.mdoel");
  EXPECT_NE(msg.find("the key 'model'"), std::string::npos) << msg;
}

TEST(ReliabilityErrors, DtFloorRatioMustBeBelowOne) {
  const std::string text = with("end_time = 1.0e-6", "end_time = 1.0e-6\ndt_floor_ratio = 1.5");
  expect_names(error_of(text), line_of(text, "dt_floor_ratio"), "solver.dt_floor_ratio");
  EXPECT_EQ(test::parse(kTinyScene).dt_floor_ratio, 1e-4);  // the default
}

}  // namespace
}  // namespace shatter::scene
