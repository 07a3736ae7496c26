// One test per kind of bad input: each checks that the scene is refused and that the message
// names the file, the line and the key at fault.

#include <gtest/gtest.h>

#include "scene_fixture.hpp"

namespace shatter::scene {
namespace {

using test::error_of;
using test::expect_names;
using test::kTinyScene;
using test::line_of;
using test::with;

TEST(SceneErrors, MisspeltKeySuggestsTheRightOne) {
  const std::string text = with("radius = 0.01", "raduis = 0.01");
  const std::string msg = error_of(text);
  expect_names(msg, line_of(text, "raduis"), "body.target.raduis");
  EXPECT_NE(msg.find("did you mean 'radius'"), std::string::npos) << msg;
}

TEST(SceneErrors, MisspeltSectionSuggestsTheRightOne) {
  const std::string text = with("[output]", "[outptu]");
  const std::string msg = error_of(text);
  expect_names(msg, line_of(text, "[outptu]"), "outptu");
  EXPECT_NE(msg.find("did you mean 'output'"), std::string::npos) << msg;
}

TEST(SceneErrors, UnknownKeyWithoutNearMatchListsTheAllowedKeys) {
  const std::string text = with("cell_size = 2.0e-3", "cell_size = 2.0e-3\ncolour = 1");
  const std::string msg = error_of(text);
  expect_names(msg, line_of(text, "colour"), "solver.colour");
  EXPECT_NE(msg.find("allowed here"), std::string::npos) << msg;
}

TEST(SceneErrors, WrongTypeNamesWhatWasExpected) {
  const std::string text = with("radius = 0.01", "radius = \"big\"");
  const std::string msg = error_of(text);
  expect_names(msg, line_of(text, "\"big\""), "body.target.radius");
  EXPECT_NE(msg.find("must be a number (got a string)"), std::string::npos) << msg;
}

TEST(SceneErrors, VectorWithWrongLengthIsRefused) {
  const std::string text = with("centre = [0.0, 0.0, 0.0]", "centre = [0.0, 0.0]");
  expect_names(error_of(text), line_of(text, "centre = [0.0, 0.0]"), "body.target.centre");
}

TEST(SceneErrors, MissingRequiredValueNamesTheTable) {
  const std::string text = with("end_time = 1.0e-6\n", "");
  const std::string msg = error_of(text);
  expect_names(msg, line_of(text, "[solver]"), "solver.end_time");
  EXPECT_NE(msg.find("required"), std::string::npos) << msg;
}

TEST(SceneErrors, MissingSolverSectionIsRefused) {
  const std::string text =
      with("[solver]\ncell_size = 2.0e-3\nend_time = 1.0e-6\nsymmetry_plane = \"z\"\n", "");
  EXPECT_NE(error_of(text).find("solver"), std::string::npos);
}

TEST(SceneErrors, NegativeRadiusIsNonPhysical) {
  const std::string text = with("radius = 0.01", "radius = -0.01");
  const std::string msg = error_of(text);
  expect_names(msg, line_of(text, "radius = -0.01"), "body.target.radius");
  EXPECT_NE(msg.find("must be > 0"), std::string::npos) << msg;
}

TEST(SceneErrors, CflAboveOneIsRefused) {
  const std::string text = with("end_time = 1.0e-6", "end_time = 1.0e-6\ncfl = 1.5");
  expect_names(error_of(text), line_of(text, "cfl"), "solver.cfl");
}

TEST(SceneErrors, ImpactAngleOutsideRangeIsRefused) {
  const std::string text = with("angle = 30.0", "angle = 95.0");
  expect_names(error_of(text), line_of(text, "angle = 95"), "impact.angle");
}

TEST(SceneErrors, UnknownShapeSuggestsTheClosest) {
  const std::string text = with("shape = \"sphere\"", "shape = \"sphre\"");
  const std::string msg = error_of(text);
  expect_names(msg, line_of(text, "sphre"), "body.target.shape");
  EXPECT_NE(msg.find("did you mean 'sphere'"), std::string::npos) << msg;
}

TEST(SceneErrors, UnknownMaterialSuggestsTheClosest) {
  const std::string text = with("material = \"basalt\"", "material = \"basalr\"");
  const std::string msg = error_of(text);
  expect_names(msg, line_of(text, "basalr"), "body.target.material");
  EXPECT_NE(msg.find("did you mean 'basalt'"), std::string::npos) << msg;
}

TEST(SceneErrors, NonPhysicalMaterialOverridePointsAtTheOverride) {
  const std::string text =
      with("material = \"basalt\"", "material = { name = \"basalt\", poisson = 0.7 }");
  const std::string msg = error_of(text);
  expect_names(msg, line_of(text, "poisson = 0.7"), "body.target.material.poisson");
}

TEST(SceneErrors, UnknownDamageParameterPointsAtIt) {
  const std::string text = with("weibull_m = 8.5", "weibul_m = 8.5");
  const std::string msg = error_of(text);
  expect_names(msg, line_of(text, "weibul_m"), "body.target.damage.weibul_m");
}

TEST(SceneErrors, OverlappingBodiesAreRefused) {
  // Without the impact helper the projectile sits where it is put: inside the target.
  std::string text = with(
      "[impact]\nprojectile = \"projectile\"\ntarget = \"target\"\n"
      "speed = 3200.0\nangle = 30.0\n",
      "");
  text = with("radius = 3.5e-3", "radius = 3.5e-3\ncentre = [0.008, 0.0, 0.0]", text);
  const std::string msg = error_of(text);
  // Bodies are taken in name order; the later one (target) is the one found overlapping.
  expect_names(msg, line_of(text, "shape = \"sphere\""), "body.target");
  EXPECT_NE(msg.find("overlaps body 'projectile'"), std::string::npos) << msg;
}

TEST(SceneErrors, MassBelowTheVaporisationDensityIsRefusedAtTheMassKey) {
  // 0.175 g in a 7 mm sphere is 974 kg/m^3, below nylon's rho_iv = 1100 (Tillotson needs
  // rho_iv < rho0).
  const std::string text = with("material = \"nylon\"", "material = \"nylon\"\nmass = 0.175e-3");
  const std::string msg = error_of(text);
  expect_names(msg, line_of(text, "mass = 0.175e-3"), "body.projectile.mass");
  EXPECT_NE(msg.find("rho_iv"), std::string::npos) << msg;
}

TEST(SceneErrors, BodyOutsideTheDomainIsRefused) {
  const std::string text = with("hi = [0.05, 0.05, 0.05]", "hi = [0.05, 0.05, 0.006]");
  const std::string msg = error_of(text);
  expect_names(msg, line_of(text, "shape = \"sphere\""), "body.target");
  EXPECT_NE(msg.find("outside the domain"), std::string::npos) << msg;
}

TEST(SceneErrors, DomainLowerFaceMustBeTheSymmetryPlane) {
  const std::string text = with("lo = [-0.05, -0.05, 0.0]", "lo = [-0.05, -0.05, -0.05]");
  expect_names(error_of(text), line_of(text, "lo = [-0.05, -0.05, -0.05]"), "domain.lo");
}

TEST(SceneErrors, ImpactOutOfTheSymmetryPlaneIsRefused) {
  const std::string text = with("angle = 30.0", "angle = 30.0\ndirection = [1.0, 0.0, 1.0]");
  expect_names(error_of(text), line_of(text, "direction"), "impact.direction");
}

TEST(SceneErrors, ImpactHelperOwnsTheProjectileCentre) {
  const std::string text = with("radius = 3.5e-3", "radius = 3.5e-3\ncentre = [0.1, 0.0, 0.0]");
  expect_names(error_of(text), line_of(text, "centre = [0.1"), "body.projectile.centre");
}

TEST(SceneErrors, ImpactNamesAMissingBody) {
  const std::string text = with("target = \"target\"", "target = \"tagret\"");
  const std::string msg = error_of(text);
  expect_names(msg, line_of(text, "tagret"), "impact.target");
}

TEST(SceneErrors, UnknownOutputColumnSuggestsTheClosest) {
  const std::string text =
      with("snapshot_every = 0.5e-6", "columns = [\"x\", \"y\", \"z\", \"damgae\"]");
  const std::string msg = error_of(text);
  expect_names(msg, line_of(text, "damgae"), "output.columns");
  EXPECT_NE(msg.find("did you mean 'damage'"), std::string::npos) << msg;
}

TEST(SceneErrors, TomlSyntaxErrorNamesTheLine) {
  const std::string text = with("radius = 0.01", "radius = = 0.01");
  const std::string msg = error_of(text);
  EXPECT_NE(msg.find("tiny.toml:" + std::to_string(line_of(text, "= = 0.01"))), std::string::npos)
      << msg;
  EXPECT_NE(msg.find("syntax"), std::string::npos) << msg;
}

TEST(SceneErrors, BadOverrideValueNamesTheCommandLine) {
  const std::string msg = error_of(kTinyScene, {"solver.cfl=-0.5"});
  EXPECT_NE(msg.find("command line (--set solver.cfl=-0.5)"), std::string::npos) << msg;
  EXPECT_NE(msg.find("solver.cfl"), std::string::npos) << msg;
}

TEST(SceneErrors, MisspeltOverrideKeySuggestsTheRightOne) {
  const std::string msg = error_of(kTinyScene, {"impact.sped=2700"});
  EXPECT_NE(msg.find("impact.sped"), std::string::npos) << msg;
  EXPECT_NE(msg.find("did you mean 'speed'"), std::string::npos) << msg;
}

TEST(SceneErrors, OverrideWithoutValueIsRefused) {
  EXPECT_NE(error_of(kTinyScene, {"impact.speed"}).find("key=value"), std::string::npos);
}

TEST(SceneErrors, BodyTooSmallForItsSpacingHasNoPoints) {
  const std::string text = with("radius = 3.5e-3", "radius = 1.0e-5");
  // The impact helper places the projectile, then the fill finds no lattice point inside.
  EXPECT_NE(error_of(text).find("has no points"), std::string::npos);
}

TEST(SceneErrors, LatticeTurnedOutOfTheSymmetryPlaneIsRefused) {
  // The tiny scene's half model (symmetry plane z): a turn about x would move points across it.
  const std::string text =
      with("radius = 0.01", "radius = 0.01\nlattice_rotation = [10.0, 0.0, 0.0]");
  const std::string msg = error_of(text);
  EXPECT_NE(msg.find("body.target.lattice_rotation"), std::string::npos) << msg;
  EXPECT_NE(msg.find("may only turn about z"), std::string::npos) << msg;
}

}  // namespace
}  // namespace shatter::scene
