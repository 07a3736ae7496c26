// solver.geometry = "axisymmetric" (issue 31): the r-z scene's points, masses and axis, a run
// through the solver, and every combination the r-z mode does not carry refused by its key and
// line (docs/scenes.md, "Axisymmetric (r-z) scenes").

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "scene_fixture.hpp"
#include "shatter/core/solver.hpp"
#include "shatter/scene/build.hpp"

namespace shatter::scene {
namespace {

using test::expect_names;
using test::line_of;

const std::string kRz = R"(name = "rz"

[solver]
geometry = "axisymmetric"
shape = "bspline2"
cell_size = 2.0e-3
end_time = 1.0e-6

[domain]
lo = [0.0, -0.05, -0.05]
hi = [0.05, 0.05, 0.05]
boundary = "outflow"

[body.target]
shape = "sphere"
centre = [0.0, 0.0, -0.02]
radius = 0.01
material = "basalt"

[body.projectile]
shape = "sphere"
radius = 3.5e-3
material = "nylon"

[impact]
projectile = "projectile"
target = "target"
speed = 3200.0
angle = 0.0
direction = [0.0, 0.0, -1.0]

[output]
fragments = false
)";

std::string rz_with(const std::string& from, const std::string& to) {
  return test::with(from, to, kRz);
}

std::string error_of(const std::string& text, const std::vector<std::string>& sets = {}) {
  return test::error_of(text, sets);
}

TEST(AxisymmetricScene, PointsAreRingsInTheHalfPlaneWithTheAxisAsSymmetryFace) {
  const Scene s = test::parse(kRz);
  EXPECT_EQ(s.solver.geometry, Geometry::axisymmetric);
  EXPECT_EQ(s.solver.domain.faces[0], BoundaryKind::symmetry);
  EXPECT_EQ(s.solver.domain.lo.x(), 0.0);
  EXPECT_EQ(s.solver.domain.faces[2], BoundaryKind::none);
  for (const BodySpec& b : s.bodies) {
    ASSERT_EQ(b.fill.volumes.size(), b.fill.points.size());
    for (const Vec3& p : b.fill.points) {
      EXPECT_GT(p.x(), 0.0);
      EXPECT_EQ(p.y(), 0.0);
    }
  }
  // The rings add up to the sphere's volume: 1 % at 5 points per radius (the sub-sampled
  // surface cells, as the 3-D fill's volume).
  const auto body = [&](const std::string& name) -> const BodySpec& {
    for (const BodySpec& b : s.bodies) {
      if (b.name == name) return b;
    }
    throw std::runtime_error("no body " + name);
  };
  const BodySpec& target = body("target");
  double v = 0.0;
  for (const double x : target.fill.volumes) v += x;
  const double exact = 4.0 / 3.0 * std::numbers::pi * 1e-6;
  EXPECT_NEAR(v / exact, 1.0, 0.01);
  EXPECT_NEAR(target.fill.volume / exact, 1.0, 0.01);
  // The head-on helper puts the projectile on the axis, moving along -z.
  const BodySpec& projectile = body("projectile");
  EXPECT_EQ(projectile.velocity, Vec3(0.0, 0.0, -3200.0));
}

// The scene through build and the solver: a few steps of the head-on impact in r-z, with the
// momentum along z conserved to round-off (1e-12 relative: the axis and the outflow faces are
// not reached).
TEST(AxisymmetricScene, RunsThroughTheSolver) {
  const Scene s = test::parse(kRz);
  BuiltScene built = build(s);
  auto solver = make_solver(s, std::move(built.particles), built.materials, 1);
  const auto pz = [&] {
    const ParticleStore& P = solver->particles();
    double sum = 0.0;
    for (std::size_t p = 0; p < P.size(); ++p) sum += P.col(Field::mass)[p] * P.col(Field::vz)[p];
    return sum;
  };
  const double before = pz();
  for (int k = 0; k < 10; ++k) solver->step();
  EXPECT_NEAR(pz(), before, 1e-12 * std::abs(before));
}

TEST(AxisymmetricScene, UnknownGeometryIsRefusedWithKeyAndLine) {
  const std::string text = rz_with("geometry = \"axisymmetric\"", "geometry = \"2d\"");
  expect_names(error_of(text), line_of(text, "geometry"), "solver.geometry");
}

TEST(AxisymmetricScene, WhatTheRzModeDoesNotCarryIsRefusedWithKeyAndLine) {
  // line_text: the text of the line the error must name (a body's errors name its table's first
  // key, shape = ...; `skip` earlier occurrences of that text are passed over).
  struct Case {
    std::string from, to, key, line_text;
    int skip = 0;
  };
  const std::vector<Case> cases = {
      {"shape = \"bspline2\"", "shape = \"ugimp\"", "solver.shape", "shape = \"ugimp\""},
      {"cell_size", "transfer = \"apic\"\ncell_size", "solver.transfer", "transfer"},
      {"cell_size", "contact = \"multi_field\"\ncell_size", "solver.contact", "contact"},
      {"cell_size", "symmetry_plane = \"z\"\ncell_size", "solver.symmetry_plane", "symmetry_plane"},
      {"cell_size", "gravity = [9.81, 0.0, 0.0]\ncell_size", "solver.gravity", "gravity"},
      {"boundary = \"outflow\"", "boundary = \"outflow\"\ny_lo = \"fixed\"", "domain.y_lo", "y_lo"},
      {"angle = 0.0", "angle = 30.0", "impact.angle", "angle = 30.0"},
      {"direction = [0.0, 0.0, -1.0]", "direction = [1.0, 0.0, 0.0]", "impact.direction",
       "direction"},
      {"centre = [0.0, 0.0, -0.02]", "centre = [0.005, 0.0, -0.02]", "body.target.centre",
       "shape = \"sphere\""},
      {"material = \"nylon\"", "material = \"nylon\"\nlattice_rotation = [0.0, 0.0, 30.0]",
       "body.projectile.lattice_rotation", "shape = \"sphere\"", 1},
      {"material = \"basalt\"",
       "material = \"basalt\"\n\n[body.target.damage]\nmodel = \"grady_kipp\"\nweibull_m = "
       "8.5\nweibull_k = 3.0e39\nexplicit_flaws = 1",
       "body.target.damage.explicit_flaws", "shape = \"sphere\""},
  };
  for (const Case& c : cases) {
    const std::string text = rz_with(c.from, c.to);
    std::size_t at = text.find(c.line_text);
    for (int k = 0; k < c.skip; ++k) at = text.find(c.line_text, at + 1);
    const int line =
        1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n'));
    expect_names(error_of(text), line, c.key);
  }
  // The fragment search knows rings (issue 31): left out, the key defaults to true in r-z and
  // the search is told the points are rings; asked for, it is accepted.
  const auto defaulted = test::parse(rz_with("fragments = false", ""));
  EXPECT_TRUE(defaulted.output.fragments);
  EXPECT_TRUE(defaulted.fracture.search.axisymmetric);
  EXPECT_TRUE(test::parse(rz_with("fragments = false", "fragments = true")).output.fragments);
  // SPH: the method, named (given with --set, so no line of the file).
  const std::string msg = error_of(kRz, {"solver.method=\"sph\""});
  EXPECT_NE(msg.find("solver.method"), std::string::npos) << msg;
  EXPECT_NE(msg.find("axisymmetric"), std::string::npos) << msg;
}

}  // namespace
}  // namespace shatter::scene
