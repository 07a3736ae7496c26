#include <fmt/format.h>

#include "scene/parts.hpp"

namespace shatter::scene {

void check_lattice_rotation(const Scene& scene, const BodySpec& b) {
  if (scene.symmetry_axis < 0) return;
  // The half model keeps the points on one side of the plane, and their mirror images must be the
  // dropped ones: the lattice may only turn about the plane's normal.
  const Vec3 n = Vec3::Unit(scene.symmetry_axis);
  if ((b.lattice_rotation * n - n).norm() > 1e-12) {
    const char axis = "xyz"[scene.symmetry_axis];
    throw SceneError(b.where, "body." + b.name + ".lattice_rotation",
                     fmt::format("with the symmetry plane normal to {} the lattice may only turn "
                                 "about {} (give only the {} angle)",
                                 axis, axis, axis));
  }
}

void fill_and_check_bodies(Scene& scene) {
  const Domain& d = scene.solver.domain;
  const bool rz = scene.solver.geometry == Geometry::axisymmetric;
  for (BodySpec& b : scene.bodies) {
    if (rz) {
      check_axisymmetric_body(b);
      b.fill = fill_lattice_rz(b.shape, b.spacing);
    } else {
      check_lattice_rotation(scene, b);
      b.fill = fill_lattice(b.shape, b.spacing, scene.symmetry_axis, b.lattice_rotation);
    }
    if (b.fill.points.empty()) {
      throw SceneError(b.where, "body." + b.name,
                       scene.symmetry_axis >= 0
                           ? "has no points: smaller than its spacing, or entirely on the "
                             "mirrored side of the symmetry plane"
                           : "has no points: smaller than its spacing");
    }
    // Every point's cell (half a spacing around it) must be inside the domain.
    for (const Vec3& p : b.fill.points) {
      const double h = 0.5 * b.spacing;
      if ((p.array() - h < d.lo.array()).any() || (p.array() + h > d.hi.array()).any()) {
        throw SceneError(b.where, "body." + b.name,
                         fmt::format("extends outside the domain (point at [{}, {}, {}] m; domain "
                                     "lo [{}, {}, {}], hi [{}, {}, {}])",
                                     p.x(), p.y(), p.z(), d.lo.x(), d.lo.y(), d.lo.z(), d.hi.x(),
                                     d.hi.y(), d.hi.z()));
      }
    }
  }
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    for (std::size_t j = i + 1; j < scene.bodies.size(); ++j) {
      const BodySpec& a = scene.bodies[i];
      const BodySpec& b = scene.bodies[j];
      if (!a.shape.bounds().intersects(b.shape.bounds())) continue;
      std::size_t inside = 0;
      for (const Vec3& p : b.fill.points) inside += a.shape.contains(p) ? 1 : 0;
      for (const Vec3& p : a.fill.points) inside += b.shape.contains(p) ? 1 : 0;
      if (inside > 0) {
        throw SceneError(
            b.where, "body." + b.name,
            fmt::format("overlaps body '{}' ({} points lie inside both)", a.name, inside));
      }
    }
  }
}

}  // namespace shatter::scene
