// The impact helper on a mesh target (issue 34 item 3): ray casting the mesh
// (MeshSolid::first_hit) gives the impact point and its normal; on a fine sphere mesh the placed
// projectile matches the analytic sphere's to the facet size; a sphere target is unchanged.

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

#include "scene_fixture.hpp"
#include "shatter/scene/mesh.hpp"
#include "shatter/scene/scene.hpp"

namespace shatter::scene {
namespace {

namespace fs = std::filesystem;
using Vec3 = Eigen::Vector3d;

// A unit UV sphere: poles at z = +-1, `lat` bands and `lon` sectors, outward (counter-clockwise
// seen from outside) unless `inward`.
std::string uv_sphere_obj(int lat, int lon, bool inward = false) {
  std::ostringstream o;
  o.precision(17);
  o << "v 0 0 1\n";
  for (int i = 1; i < lat; ++i) {
    const double th = std::numbers::pi * i / lat;
    for (int j = 0; j < lon; ++j) {
      const double ph = 2.0 * std::numbers::pi * j / lon;
      o << "v " << std::sin(th) * std::cos(ph) << ' ' << std::sin(th) * std::sin(ph) << ' '
        << std::cos(th) << '\n';
    }
  }
  o << "v 0 0 -1\n";
  const int south = 2 + (lat - 1) * lon;  // 1-based OBJ indices
  auto ring = [&](int i, int j) { return 2 + (i - 1) * lon + (j % lon); };
  auto tri = [&](int a, int b, int c) {
    if (inward) std::swap(b, c);
    o << "f " << a << ' ' << b << ' ' << c << '\n';
  };
  for (int j = 0; j < lon; ++j) {
    tri(1, ring(1, j), ring(1, j + 1));
    for (int i = 1; i + 1 < lat; ++i) {
      tri(ring(i, j), ring(i + 1, j), ring(i + 1, j + 1));
      tri(ring(i, j), ring(i + 1, j + 1), ring(i, j + 1));
    }
    tri(south, ring(lat - 1, j + 1), ring(lat - 1, j));
  }
  return o.str();
}

struct Dir {
  fs::path path = fs::temp_directory_path() / ("shatter_impact_mesh_" + std::to_string(::getpid()));
  Dir() { fs::create_directories(path); }
  ~Dir() { fs::remove_all(path); }
};

TEST(ImpactMesh, RayHitsTheNearSurfaceWithTheOutwardNormalWhateverTheWinding) {
  Dir dir;
  for (bool inward : {false, true}) {
    std::ofstream(dir.path / "ball.obj") << uv_sphere_obj(16, 32, inward);
    const MeshSolid ball(read_mesh(dir.path / "ball.obj"));
    const auto hit = ball.first_hit(Vec3(-5.0, 0.01, 0.02), Vec3::UnitX());
    ASSERT_TRUE(hit.has_value());
    // The near side at x ~ -1 (within the facets' sag, 1 - cos(pi / 16) = 2 %).
    EXPECT_NEAR(hit->point.x(), -1.0, 0.02);
    EXPECT_NEAR(hit->t, 5.0 + hit->point.x(), 1e-12);
    EXPECT_LT(hit->normal.x(), -0.95) << inward;
    EXPECT_NEAR(hit->normal.norm(), 1.0, 1e-12);
    EXPECT_FALSE(ball.first_hit(Vec3(-5.0, 2.0, 0.0), Vec3::UnitX()).has_value());
  }
}

std::string mesh_target_scene() {
  std::string s = test::kTinyScene;
  const std::string from = "shape = \"sphere\"\ncentre = [0.0, 0.0, 0.0]\nradius = 0.01\n";
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos);
  s.replace(at, from.size(), "shape = \"mesh\"\nfile = \"ball.obj\"\nscale = 0.01\n");
  return s;
}

TEST(ImpactMesh, FineSphereMeshIsAimedAsTheSphere) {
  Dir dir;
  std::ofstream(dir.path / "ball.obj") << uv_sphere_obj(48, 96);
  const Scene sphere = parse_scene(test::kTinyScene, "tiny.toml", {}, dir.path);
  const Scene mesh = parse_scene(mesh_target_scene(), "mesh.toml", {}, dir.path);
  ASSERT_TRUE(mesh.impact.used);
  // The hit facet's normal is the first at >= 30 degrees: past it by less than a facet's angular
  // size (360 / 96 = 3.75 degrees).
  EXPECT_GE(mesh.impact.angle_deg, 30.0);
  EXPECT_LT(mesh.impact.angle_deg, 30.0 + 3.75);
  // Impact point and projectile centre within the facet size (R pi / 48 = 0.65 mm) of the
  // analytic sphere's.
  EXPECT_LT((mesh.impact.impact_point - sphere.impact.impact_point).norm(), 0.01 * 0.07);
  EXPECT_LT((mesh.impact.projectile_centre - sphere.impact.projectile_centre).norm(), 0.01 * 0.07);
  // In the symmetry plane, as the half model needs.
  EXPECT_EQ(mesh.impact.impact_point.z(), 0.0);
  EXPECT_EQ(mesh.impact.projectile_centre.z(), 0.0);
  // Same velocity as the sphere's.
  const auto body = [](const Scene& s, const char* name) {
    for (const auto& b : s.bodies)
      if (b.name == name) return b;
    ADD_FAILURE() << name;
    return s.bodies.front();
  };
  EXPECT_EQ(body(mesh, "projectile").velocity, body(sphere, "projectile").velocity);
}

TEST(ImpactMesh, CoarseMeshReportsTheAngleOfItsFacetAndTheProjectileClearsIt) {
  Dir dir;
  fs::copy_file(fs::path(SHATTER_SOURCE_DIR) / "data" / "meshes" / "icosahedron.obj",
                dir.path / "ball.obj");
  std::string text = mesh_target_scene();
  text.replace(text.find("symmetry_plane = \"z\"\n"), 21, "");
  text.replace(text.find("lo = [-0.05, -0.05, 0.0]"), 24, "lo = [-0.05, -0.05, -0.05]");
  // Seen along x in the x-y plane, the icosahedron's faces are at 20.905 degrees (normal
  // (-0.934, +-0.357, 0)) up to its silhouette: no ray there meets a face at 30 degrees.
  std::string msg;
  try {
    parse_scene(text, "mesh.toml", {}, dir.path);
  } catch (const SceneError& e) {
    msg = e.what();
  }
  EXPECT_NE(msg.find("impact.angle: no ray along impact.direction"), std::string::npos) << msg;
  text.replace(text.find("angle = 30.0"), 12, "angle = 20.0");
  const Scene s = parse_scene(text, "mesh.toml", {}, dir.path);
  const double angle = s.impact.angle_deg;
  // acos(0.934172) of the face hit (normal -(phi^2, 1, 0) / |.| for the edge-2 icosahedron).
  const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
  EXPECT_NEAR(
      angle,
      std::acos(phi * phi / std::sqrt(phi * phi * phi * phi + 1.0)) * 180.0 / std::numbers::pi,
      1e-9);
  // The projectile touches the surface at the impact point along the facet normal, one gap back.
  const Vec3 n =
      (s.impact.projectile_centre - s.impact.impact_point + s.solver.cell_size * Vec3::UnitX());
  double r = 0.0;
  for (const auto& b : s.bodies)
    if (b.name == "projectile") r = std::get<Sphere>(b.shape.parts[0]).radius;
  EXPECT_NEAR(n.norm(), r, 1e-15);
  // The angle reported is the one between that normal and the reversed velocity (-x).
  EXPECT_NEAR(std::acos(-n.normalized().x()) * 180.0 / std::numbers::pi, angle, 1e-9);
}

TEST(ImpactMesh, SphereTargetPlacementIsTheAnalyticFormulaBitForBit) {
  const Scene s = parse_scene(test::kTinyScene, "tiny.toml", {}, ".");
  const double alpha = 30.0 * std::numbers::pi / 180.0;
  const Vec3 n = -std::cos(alpha) * Vec3::UnitX() + std::sin(alpha) * Vec3::UnitY();
  double rp = 0.0;
  for (const auto& b : s.bodies)
    if (b.name == "projectile") rp = std::get<Sphere>(b.shape.parts[0]).radius;
  EXPECT_EQ(s.impact.impact_point, Vec3(Vec3::Zero() + 0.01 * n));
  EXPECT_EQ(s.impact.projectile_centre,
            Vec3(Vec3::Zero() + (0.01 + rp) * n - s.solver.cell_size * Vec3::UnitX()));
  EXPECT_EQ(s.impact.angle_deg, 30.0);
}

}  // namespace
}  // namespace shatter::scene
