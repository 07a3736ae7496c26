// A mesh of two overlapping closed shells (issue 33 item 7): ray parity left the overlap empty
// (a body with a hole, no message). The inside test is now the winding number, which fills the
// overlap, and the scene reader refuses such a mesh naming the file and a point enclosed twice.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "shatter/scene/mesh.hpp"
#include "shatter/scene/scene.hpp"

namespace shatter::scene {
namespace {

namespace fs = std::filesystem;
using Vec3 = Eigen::Vector3d;

// The unit cube's 12 outward triangles (vertex k at bits (x, y, z) of k).
const int kFaces[12][3] = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                           {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};

// One cube per entry of `shifts` (each closed, outward), in one mesh.
TriangleMesh cubes(const std::vector<Vec3>& shifts) {
  TriangleMesh m;
  for (const Vec3& s : shifts) {
    const auto base = static_cast<std::uint32_t>(m.vertices.size());
    for (int k = 0; k < 8; ++k) {
      m.vertices.push_back(s + Vec3(k & 1, (k >> 1) & 1, (k >> 2) & 1));
    }
    for (const auto& f : kFaces) {
      m.triangles.push_back({base + static_cast<std::uint32_t>(f[0]),
                             base + static_cast<std::uint32_t>(f[1]),
                             base + static_cast<std::uint32_t>(f[2])});
    }
  }
  return m;
}

std::string obj_of(const TriangleMesh& m) {
  std::string s;
  for (const Vec3& v : m.vertices) {
    s += "v " + std::to_string(v.x()) + " " + std::to_string(v.y()) + " " + std::to_string(v.z()) +
         "\n";
  }
  for (const auto& t : m.triangles) {
    s += "f " + std::to_string(t[0] + 1) + " " + std::to_string(t[1] + 1) + " " +
         std::to_string(t[2] + 1) + "\n";
  }
  return s;
}

TEST(MeshOverlap, OneCubeHasWindingOneInsideAndZeroOutside) {
  const MeshSolid cube(cubes({Vec3::Zero()}));
  EXPECT_EQ(std::abs(cube.winding({0.5, 0.5, 0.5})), 1);
  EXPECT_EQ(cube.winding({1.5, 0.5, 0.5}), 0);
  EXPECT_EQ(cube.winding({0.5, 0.5, -0.5}), 0);
  EXPECT_FALSE(cube.find_overlap(32).has_value());
}

TEST(MeshOverlap, OverlapOfTwoShellsIsInsideAndFound) {
  // Cubes [0, 1]^3 and [0.5, 1.5] x [0, 1]^2 (offset in y/z by a little, so the rays do not run
  // along shared faces): their overlap x in (0.5, 1) was outside by parity.
  const MeshSolid two(cubes({Vec3::Zero(), Vec3(0.5, 0.01, 0.02)}));
  const Vec3 overlap(0.75, 0.5, 0.5);
  EXPECT_EQ(std::abs(two.winding(overlap)), 2);
  EXPECT_TRUE(two.contains(overlap));
  EXPECT_TRUE(two.contains({0.25, 0.5, 0.5}));
  EXPECT_TRUE(two.contains({1.25, 0.5, 0.5}));
  EXPECT_FALSE(two.contains({1.75, 0.5, 0.5}));
  const auto found = two.find_overlap(32);
  ASSERT_TRUE(found.has_value());
  EXPECT_EQ(std::abs(two.winding(*found)), 2);
}

TEST(MeshOverlap, SceneWithOverlappingShellsIsRefusedNamingTheFile) {
  const fs::path dir =
      fs::temp_directory_path() / ("shatter_mesh_overlap_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "two.obj") << obj_of(cubes({Vec3::Zero(), Vec3(0.5, 0.01, 0.02)}));
  std::ofstream(dir / "apart.obj") << obj_of(cubes({Vec3::Zero(), Vec3(2.0, 0.0, 0.0)}));
  auto scene = [](const std::string& file) {
    return "[solver]\ncell_size = 2.0e-3\nend_time = 1.0e-6\n\n[body.rock]\nmaterial = "
           "\"basalt\"\nshape = \"mesh\"\nscale = 0.01\nfile = \"" +
           file + "\"\n";
  };
  std::string msg;
  try {
    parse_scene(scene("two.obj"), "mesh.toml", {}, dir);
  } catch (const SceneError& e) {
    msg = e.what();
  }
  EXPECT_NE(msg.find("two.obj: the surface encloses the point"), std::string::npos) << msg;
  EXPECT_NE(msg.find("more than once"), std::string::npos) << msg;
  // Two separate shells are one body with two parts, as before.
  EXPECT_NO_THROW(parse_scene(scene("apart.obj"), "mesh.toml", {}, dir));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace shatter::scene
