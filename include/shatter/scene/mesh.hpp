#pragma once
// Body shapes from closed triangle meshes (spacecraft shape models of asteroids are published as
// OBJ or STL): reading, the closed-surface check, and a point-in-solid test by ray parity.

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace shatter::scene {

struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;  // vertex indices
};

// Reads Wavefront OBJ (v and f records; polygons are split into triangle fans; other records
// are ignored) or STL (ASCII, or binary: 80-byte header, count, 50 bytes per triangle; STL
// vertices are joined where their coordinates are equal), chosen by the extension (.obj, .stl).
// Throws std::invalid_argument naming the file and, for text, the line.
TriangleMesh read_mesh(const std::filesystem::path& file);

// Throws std::invalid_argument unless every edge is shared by exactly two triangles that use it
// in opposite directions (a closed, consistently oriented surface); the message says how many
// edges are open, shared by more than two triangles or oriented the same way, with an example.
void check_closed(const TriangleMesh& mesh);

// The solid a closed mesh encloses, for the lattice fill: an inside test that casts a ray along
// +z and sums the triangles it crosses, +1 for one facing +z and -1 for one facing -z (the
// winding number; non-zero = inside). For a simple closed surface it is 0 or +-1 wherever
// parity says outside or inside; where two closed shells of one mesh overlap it is +-2, so the
// overlap is filled (ray parity left it empty: issue 33). A ray through an edge or a vertex
// shared by several triangles is counted once: each projected edge belongs to exactly one side
// (the top-left rule of rasterisers), decided on the edge's canonical direction so both
// triangles agree bit for bit. Triangles are binned on a grid in x-y, so a test costs a few
// triangles, not all of them.
class MeshSolid {
 public:
  explicit MeshSolid(TriangleMesh mesh);

  bool contains(const Eigen::Vector3d& p) const;
  // The winding number of the surface about p (0 outside; +-1 inside a simple closed surface).
  int winding(const Eigen::Vector3d& p) const;
  // A point of an n x n x n grid of cell centres over the bounding box enclosed more than once
  // (overlapping shells or a self-intersecting surface), if there is one.
  std::optional<Eigen::Vector3d> find_overlap(int n) const;
  const Eigen::Vector3d& lo() const { return lo_; }
  const Eigen::Vector3d& hi() const { return hi_; }
  // Enclosed volume by the divergence theorem (sum of signed tetrahedra from the origin).
  double volume() const { return volume_; }
  std::size_t triangle_count() const { return mesh_.triangles.size(); }
  // The first crossing of the surface by the ray origin + t dir (t > 0, dir a unit vector): the
  // distance t, the point, and the outward unit normal of the triangle hit
  // (src/scene/mesh_ray.cpp).
  struct RayHit {
    double t = 0.0;
    Eigen::Vector3d point, normal;
  };
  std::optional<RayHit> first_hit(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir) const;

 private:
  TriangleMesh mesh_;
  Eigen::Vector3d lo_, hi_;
  double volume_ = 0.0;
  double orientation_ = 1.0;  // +1 when the triangles wind counter-clockwise seen from outside
  int nx_ = 1, ny_ = 1;
  double bin_x_ = 1.0, bin_y_ = 1.0;
  std::vector<std::vector<std::uint32_t>> bins_;  // triangles whose x-y box meets the bin
};

}  // namespace shatter::scene
