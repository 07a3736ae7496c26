// Ray casting on a closed triangle mesh, for aiming the impact helper at any target surface
// (src/scene/impact.cpp): Moller & Trumbore (1997), "Fast, minimum storage ray-triangle
// intersection", J. Graphics Tools 2(1), Sec. 2 (barycentric u, v and distance t by Cramer's
// rule). A ray is cast once per aim, so every triangle is tested (no acceleration structure).

#include <cmath>
#include <limits>
#include <optional>

#include <Eigen/Geometry>

#include "shatter/scene/mesh.hpp"

namespace shatter::scene {

std::optional<MeshSolid::RayHit> MeshSolid::first_hit(const Eigen::Vector3d& origin,
                                                      const Eigen::Vector3d& dir) const {
  std::optional<RayHit> best;
  double best_t = std::numeric_limits<double>::infinity();
  const double scale = (hi_ - lo_).norm();
  for (const auto& tri : mesh_.triangles) {
    const Eigen::Vector3d& a = mesh_.vertices[tri[0]];
    const Eigen::Vector3d e1 = mesh_.vertices[tri[1]] - a;
    const Eigen::Vector3d e2 = mesh_.vertices[tri[2]] - a;
    const Eigen::Vector3d p = dir.cross(e2);
    const double det = e1.dot(p);
    // A ray in the triangle's plane (|det| ~ 0 relative to the triangle's size) misses it.
    if (std::abs(det) <= 1e-14 * e1.norm() * e2.norm()) continue;
    const double inv = 1.0 / det;
    const Eigen::Vector3d s = origin - a;
    const double u = s.dot(p) * inv;  // Moller & Trumbore (1997) Eq. 5
    if (u < 0.0 || u > 1.0) continue;
    const Eigen::Vector3d q = s.cross(e1);
    const double v = dir.dot(q) * inv;
    if (v < 0.0 || u + v > 1.0) continue;
    const double t = e2.dot(q) * inv;
    if (t <= 1e-12 * scale || t >= best_t) continue;
    best_t = t;
    // Outward: the triangle's winding normal times the mesh's orientation (signed volume).
    const Eigen::Vector3d n = orientation_ * e1.cross(e2).normalized();
    best = RayHit{t, origin + t * dir, n};
  }
  return best;
}

}  // namespace shatter::scene
