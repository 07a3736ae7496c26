#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>

#include "../io/scratch_dir.hpp"
#include "scene_fixture.hpp"

namespace shatter::scene {
namespace {

using test::kTinyScene;
using test::parse;
using test::with;

TEST(SceneParse, ReadsSolverDomainAndDefaults) {
  const Scene s = parse(kTinyScene);
  EXPECT_EQ(s.name, "tiny");
  EXPECT_EQ(s.solver.cell_size, 2.0e-3);
  EXPECT_EQ(s.end_time, 1.0e-6);
  EXPECT_EQ(s.solver.shape, ShapeKind::ugimp);
  EXPECT_EQ(s.solver.cfl, 0.3);
  EXPECT_EQ(s.symmetry_axis, 2);
  EXPECT_EQ(s.solver.domain.faces[4], BoundaryKind::symmetry);  // z_lo is the mirror plane
  EXPECT_EQ(s.solver.domain.faces[5], BoundaryKind::outflow);
  EXPECT_EQ(s.solver.domain.lo.z(), 0.0);
  ASSERT_EQ(s.bodies.size(), 2u);
  // Bodies come in name order: group 0 = projectile, group 1 = target.
  EXPECT_EQ(s.bodies[0].name, "projectile");
  EXPECT_EQ(s.bodies[1].name, "target");
  EXPECT_EQ(s.bodies[1].spacing, 1.0e-3);  // 2 points per cell by default
  EXPECT_EQ(s.bodies[1].damage.model, "grady_kipp");
  ASSERT_TRUE(s.bodies[1].flaws.has_value());
  EXPECT_EQ(s.bodies[1].flaws->weibull_m, 8.5);
  EXPECT_EQ(s.bodies[1].flaws->young, 53.1e9);
  EXPECT_FALSE(s.bodies[0].flaws.has_value());
  EXPECT_EQ(s.output.snapshot_every, 0.5e-6);
  EXPECT_EQ(s.output.directory, "out/tiny");
  EXPECT_EQ(s.fracture.threshold, 0.9);
}

TEST(SceneParse, DomainBoundsSnapOutwardToGridPlanes) {
  const Scene s = parse(with("hi = [0.05, 0.05, 0.05]", "hi = [0.0501, 0.05, 0.05]"));
  EXPECT_NEAR(s.solver.domain.hi.x(), 0.052, 1e-15);  // next multiple of the 2 mm cell
  EXPECT_NEAR(s.solver.domain.lo.x(), -0.05, 1e-15);
}

TEST(SceneParse, ImpactHelperPlacesTheProjectileAsInFig4) {
  const Scene s = parse(kTinyScene);
  const auto& target = std::get<Sphere>(s.bodies[1].shape.parts[0]);
  const auto& proj = std::get<Sphere>(s.bodies[0].shape.parts[0]);
  const Vec3 d = Vec3::UnitX();
  // Impact point offset from the target centre by R sin(30 deg) = R/2 across the velocity.
  EXPECT_NEAR(s.impact.impact_point.y(), 0.5 * target.radius, 1e-15);
  EXPECT_NEAR((s.impact.impact_point - target.centre).norm(), target.radius, 1e-15);
  // The angle between the velocity and the inward normal at the impact point is 30 degrees.
  const Vec3 n = (s.impact.impact_point - target.centre).normalized();
  EXPECT_NEAR(std::acos(-n.dot(d)) * 180.0 / std::numbers::pi, 30.0, 1e-10);
  // The projectile sits on the outward normal, one cell (the default gap) back along -v.
  const Vec3 touching = s.impact.impact_point + proj.radius * n;
  EXPECT_NEAR((proj.centre - (touching - 2.0e-3 * d)).norm(), 0.0, 1e-15);
  EXPECT_EQ(s.bodies[0].velocity, Vec3(3200.0, 0.0, 0.0));
  EXPECT_EQ(s.bodies[1].velocity, Vec3::Zero());
}

TEST(SceneParse, HeadOnImpactHitsTheTargetCentreLine) {
  const Scene s = parse(kTinyScene, {"impact.angle=0"});
  EXPECT_NEAR(s.impact.projectile_centre.y(), 0.0, 1e-15);
  EXPECT_LT(s.impact.projectile_centre.x(), -0.01);
}

TEST(SceneParse, OverridesReplaceValuesAndAcceptBareStrings) {
  const Scene s = parse(kTinyScene, {"impact.speed=2700", "body.target.material=granite",
                                     "solver.shape=\"linear\"", "output.directory=runs/a"});
  EXPECT_EQ(s.bodies[0].velocity.x(), 2700.0);
  EXPECT_EQ(s.bodies[1].material.name, "granite");
  EXPECT_EQ(s.solver.shape, ShapeKind::linear);
  EXPECT_EQ(s.output.directory, "runs/a");
}

TEST(SceneParse, OverrideCanAddKeysAndTables) {
  const Scene s =
      parse(kTinyScene, {"body.target.material.name=basalt", "body.target.material.yield=3.0e7",
                         "solver.viscosity.linear=0.1"});
  EXPECT_EQ(s.bodies[1].material.params.at("yield"), 3.0e7);
  EXPECT_EQ(s.solver.viscosity.linear, 0.1);
}

TEST(SceneParse, ProjectileMassChangesDensityKeepingVolume) {
  // MPM paper Table 2: projectile mass 0.175 g by density at constant volume.
  const Scene s = parse(kTinyScene, {"body.projectile.mass=0.225e-3"});
  const double v = 4.0 / 3.0 * std::numbers::pi * std::pow(3.5e-3, 3);
  EXPECT_NEAR(s.bodies[0].material.params.at("rho0"), 0.225e-3 / v, 1e-9);
  // The lighter variant needs the Tillotson rho_iv lowered with it (a material override).
  const Scene light =
      parse(kTinyScene, {"body.projectile.mass=0.175e-3", "body.projectile.material.rho_iv=900"});
  EXPECT_NEAR(light.bodies[0].material.params.at("rho0"), 0.175e-3 / v, 1e-9);
}

TEST(SceneParse, MaterialOverridesApplyOnTopOfTheCatalogue) {
  const Scene s =
      parse(with("material = \"basalt\"", "material = { name = \"basalt\", yield = 60.0e6 }"));
  EXPECT_EQ(s.bodies[1].material.params.at("yield"), 60.0e6);
  EXPECT_EQ(s.bodies[1].material.params.at("rho0"), 2700.0);
}

TEST(SceneParse, ResolvedSceneReparsesToTheSameScene) {
  const Scene a = parse(kTinyScene, {"impact.angle=45"});
  // Defaults are written out so the resolved scene does not depend on this version's defaults.
  EXPECT_NE(a.resolved.find("cfl = "), std::string::npos) << a.resolved;
  EXPECT_NE(a.resolved.find("quadratic = "), std::string::npos) << a.resolved;
  EXPECT_NE(a.resolved.find("angle = 45"), std::string::npos) << a.resolved;
  const Scene b = scene::parse_scene(a.resolved, "resolved.toml");
  EXPECT_EQ(b.resolved, a.resolved);
  EXPECT_EQ(b.solver.cfl, a.solver.cfl);
  EXPECT_EQ(b.solver.viscosity.quadratic, a.solver.viscosity.quadratic);
  ASSERT_EQ(b.particle_count(), a.particle_count());
  for (std::size_t i = 0; i < a.bodies.size(); ++i) {
    EXPECT_EQ(b.bodies[i].velocity, a.bodies[i].velocity);
    EXPECT_EQ(b.bodies[i].fill.volume, a.bodies[i].fill.volume);
    EXPECT_EQ(b.bodies[i].material.params, a.bodies[i].material.params);
    EXPECT_EQ(b.bodies[i].fill.points, a.bodies[i].fill.points);
  }
}

TEST(SceneParse, ResolvedSceneKeepsNonRoundNumbersExactly) {
  const Scene a = parse(kTinyScene, {"solver.end_time=0.1234567890123456789e-5"});
  const Scene b = scene::parse_scene(a.resolved, "resolved.toml");
  EXPECT_EQ(b.end_time, a.end_time);
}

TEST(SceneParse, ExtendsMergesABaseSceneAndErrorsNameTheRightFile) {
  test::ScratchDir dir;
  std::ofstream(dir / "base.toml") << kTinyScene;
  std::ofstream(dir / "variant.toml") << "extends = \"base.toml\"\n[impact]\nangle = 45.0\n";
  const Scene s = load_scene(dir / "variant.toml");
  EXPECT_EQ(s.impact.angle_deg, 45.0);
  EXPECT_EQ(s.impact.speed, 3200.0);
  EXPECT_EQ(s.resolved.find("extends"), std::string::npos);

  std::ofstream(dir / "bad.toml") << "extends = \"base.toml\"\n\n[impact]\nangle = 99.0\n";
  try {
    load_scene(dir / "bad.toml");
    FAIL() << "expected SceneError";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.toml:4"), std::string::npos) << e.what();
  }
}

TEST(SceneParse, ExtendsOfAMissingFileIsAnError) {
  test::ScratchDir dir;
  std::ofstream(dir / "v.toml") << "extends = \"nope.toml\"\n";
  EXPECT_THROW(load_scene(dir / "v.toml"), SceneError);
}

TEST(SceneParse, MissingSceneFileIsAnError) {
  EXPECT_THROW(load_scene("/nonexistent/scene.toml"), SceneError);
}

TEST(SceneParse, UnionBodiesAreAccepted) {
  std::string text = with(
      "[impact]\nprojectile = \"projectile\"\ntarget = \"target\"\n"
      "speed = 3200.0\nangle = 30.0\n",
      "");
  text = with("shape = \"sphere\"\nradius = 3.5e-3",
              "shape = \"union\"\nparts = [ { shape = \"box\", lo = [0.02, 0.0, 0.0], hi = "
              "[0.03, 0.01, 0.01] },\n  { shape = \"cylinder\", centre = [0.025, 0.005, 0.005], "
              "axis = [1.0, 0.0, 0.0], radius = 0.004, length = 0.03 } ]",
              text);
  const Scene s = parse(text);
  EXPECT_EQ(s.bodies[0].shape.parts.size(), 2u);
  EXPECT_GT(s.bodies[0].fill.points.size(), 0u);
}

}  // namespace
}  // namespace shatter::scene
