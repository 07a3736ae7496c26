// The impact helper (MPM paper Sec. 4.1, Fig. 4): the projectile touches the target at the
// impact point P = C_t + R n, where the surface normal n makes the impact angle alpha with the
// reversed velocity, so P is offset by R sin(alpha) perpendicular to the velocity (half the
// radius at 30 degrees, as in Nakamura & Fujiwara 1991). A mesh target (any shape model) is aimed
// by ray casting: rays along the impact direction, offset from the centre of its bounding box
// along impact.offset, the first whose hit has a surface normal at >= alpha from the reversed
// velocity is the impact point; the impact angle is that normal's (reported).

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "scene/parts.hpp"
#include "scene/ranges.hpp"
#include "shatter/scene/mesh.hpp"

namespace shatter::scene {
namespace {

BodySpec* find_body(Scene& scene, const std::string& name) {
  for (auto& b : scene.bodies) {
    if (b.name == name) return &b;
  }
  return nullptr;
}

struct Aim {
  Vec3 point, normal;
  double angle_deg = 0.0;  // between the normal and the reversed velocity
};

// The angle in degrees between the surface normal n and the reversed velocity -d.
double angle_to(const Vec3& n, const Vec3& d) {
  return std::acos(std::clamp(-n.dot(d), -1.0, 1.0)) * 180.0 / std::numbers::pi;
}

// The ray at offset b from the reference point hits the mesh at a normal making the angle
// angle_to(n, d). Scanning b outward from 0 in steps of 1/512 of the half diagonal, then
// bisecting the first step whose hit angle reaches alpha (60 halvings: the offset to round-off),
// gives the first such hit: on a sphere, b = R sin(alpha), the analytic impact point.
Aim aim_at_mesh(const MeshSolid& mesh, const ImpactInput& in, int axis, const SceneError& miss) {
  const Vec3 ref = 0.5 * (mesh.lo() + mesh.hi());
  const double half = 0.5 * (mesh.hi() - mesh.lo()).norm();
  const Vec3& d = in.direction;
  auto cast = [&](double b) { return mesh.first_hit(ref + b * in.offset - 4.0 * half * d, d); };
  auto reaches = [&](const std::optional<MeshSolid::RayHit>& h) {
    if (!h.has_value()) return false;
    Vec3 n = h->normal;
    if (axis >= 0) n[axis] = 0.0;
    return n.norm() > 0.0 && angle_to(n.normalized(), d) >= in.angle_deg;
  };
  // A ray through an edge or a vertex can slip between the triangles there (round-off): such a
  // miss counts as not reaching alpha, and the scan goes on.
  auto h = cast(0.0);
  double lo = 0.0, hi = 0.0;
  if (!reaches(h)) {
    constexpr int kSteps = 512;
    int k = 1;
    for (; k <= kSteps; ++k) {
      hi = half * k / kSteps;
      if (reaches(cast(hi))) break;
      lo = hi;
    }
    if (k > kSteps) throw miss;
    for (int it = 0; it < 60; ++it) {
      const double mid = 0.5 * (lo + hi);
      (reaches(cast(mid)) ? hi : lo) = mid;
    }
    h = cast(hi);
    if (!h) throw miss;
  }
  Vec3 n = h->normal;
  // On the symmetry plane of a half model the mesh's two halves mirror each other: the ray runs
  // in the plane, along an edge or across facets on both sides, whose mean normal lies in the
  // plane. Dropping the normal component keeps the projectile in the plane.
  if (axis >= 0) {
    n[axis] = 0.0;
    n.normalize();
  }
  return {h->point, n, angle_to(n, d)};
}

}  // namespace

std::optional<ImpactInput> read_impact(Reader& root, const Scene& scene) {
  toml::table* t = root.subtable("impact");
  if (t == nullptr) return std::nullopt;
  Reader r(*t, "impact", root.where("impact"));
  r.allow({"projectile", "target", "speed", "angle", "direction", "offset", "gap"});
  r.reject_unknown();
  ImpactInput in;
  in.projectile = r.string("projectile");
  in.target = r.string("target");
  in.where_projectile = r.where("projectile");
  in.where_target = r.where("target");
  if (in.projectile == in.target) r.fail("target", "must differ from impact.projectile");
  in.speed = r.positive("speed", r.number("speed"));
  r.within("speed", in.speed, 0.0, ranges::kMaxSpeed, "m/s", ranges::kSpeedReason);
  in.angle_deg = r.number("angle");
  r.note_range("angle", "[0, 90) from the surface normal", "degrees");
  if (!(in.angle_deg >= 0.0 && in.angle_deg < 90.0)) {
    r.fail("angle", fmt::format("must be in [0, 90) degrees from the surface normal (got {})",
                                in.angle_deg));
  }
  in.direction = r.vec3("direction", Vec3::UnitX());
  if (!(in.direction.norm() > 0.0)) r.fail("direction", "must not be the zero vector");
  in.direction.normalize();
  in.offset = r.vec3("offset", Vec3::UnitY());
  in.offset -= in.offset.dot(in.direction) * in.direction;
  if (!(in.offset.norm() > 1e-9)) r.fail("offset", "must not be parallel to impact.direction");
  in.offset.normalize();
  // One cell of clearance: the two bodies do not share grid nodes before contact.
  r.note_default("gap", "cell_size");
  in.gap = r.non_negative("gap", r.number("gap", scene.solver.cell_size));
  r.within("gap", in.gap, 0.0, ranges::kMaxLength, "m", ranges::kLengthReason);
  const int a = scene.symmetry_axis;
  if (a >= 0) {
    // The half model is exact only if the symmetry plane is the impact plane.
    if (std::abs(in.direction[a]) > 1e-12) {
      r.fail("direction", fmt::format("must lie in the symmetry plane {} = 0", "xyz"[a]));
    }
    if (std::abs(in.offset[a]) > 1e-12) {
      r.fail("offset", fmt::format("must lie in the symmetry plane {} = 0", "xyz"[a]));
    }
  }
  if (scene.solver.geometry == Geometry::axisymmetric) {
    // r-z: the projectile moves along the axis of symmetry (issue 31: head-on impacts only).
    if (in.angle_deg != 0.0) {
      r.fail("angle",
             "must be 0 with solver.geometry = \"axisymmetric\" (head-on impacts only; "
             "an oblique impact has no axis of symmetry)");
    }
    if (std::abs(std::abs(in.direction.z()) - 1.0) > 1e-12) {
      r.fail("direction",
             "must be along z ([0, 0, -1] or [0, 0, 1]) with solver.geometry = "
             "\"axisymmetric\" (the axis of symmetry is z)");
    }
  }
  in.where_direction = r.where("direction");
  in.where_offset = r.where("offset");
  return in;
}

void apply_impact(const ImpactInput& in, Scene& scene) {
  BodySpec* target = find_body(scene, in.target);
  if (target == nullptr) {
    throw SceneError(in.where_target, "impact.target", fmt::format("no body '{}'", in.target));
  }
  BodySpec* projectile = find_body(scene, in.projectile);
  if (projectile == nullptr) {
    throw SceneError(in.where_projectile, "impact.projectile",
                     fmt::format("no body '{}'", in.projectile));
  }
  const auto* ts =
      target->shape.parts.size() == 1 ? std::get_if<Sphere>(&target->shape.parts[0]) : nullptr;
  const auto* tm =
      target->shape.parts.size() == 1 ? std::get_if<Mesh>(&target->shape.parts[0]) : nullptr;
  if (ts == nullptr && tm == nullptr) {
    throw SceneError(
        in.where_target, "impact.target",
        fmt::format("body '{}' must be a sphere or a mesh for the impact helper", in.target));
  }
  const int a = scene.symmetry_axis;
  const Vec3 target_centre = ts != nullptr ? ts->centre : 0.5 * (tm->solid->lo() + tm->solid->hi());
  if (a >= 0 && target_centre[a] != 0.0) {
    throw SceneError(target->where, fmt::format("body.{}.centre", in.target),
                     fmt::format("must lie on the symmetry plane {} = 0", "xyz"[a]));
  }
  auto& ps = std::get<Sphere>(projectile->shape.parts[0]);

  Vec3 impact_point;
  double angle_deg = in.angle_deg;
  if (ts != nullptr) {
    const double alpha = in.angle_deg * std::numbers::pi / 180.0;
    const Vec3 n = -std::cos(alpha) * in.direction + std::sin(alpha) * in.offset;
    impact_point = ts->centre + ts->radius * n;
    ps.centre = ts->centre + (ts->radius + ps.radius) * n - in.gap * in.direction;
  } else {
    const SceneError miss(in.where_direction, "impact.angle",
                          fmt::format("no ray along impact.direction offset along impact.offset "
                                      "hits mesh body '{}' at {} degrees from its normal",
                                      in.target, in.angle_deg));
    const Aim aim = aim_at_mesh(*tm->solid, in, a, miss);
    impact_point = aim.point;
    angle_deg = aim.angle_deg;
    // Touching at the impact point along the local normal (the sphere's rule, P + r n).
    ps.centre = aim.point + ps.radius * aim.normal - in.gap * in.direction;
  }
  projectile->velocity = target->velocity + in.speed * in.direction;

  scene.impact.used = true;
  scene.impact.projectile = in.projectile;
  scene.impact.target = in.target;
  scene.impact.speed = in.speed;
  scene.impact.angle_deg = angle_deg;
  scene.impact.impact_point = impact_point;
  scene.impact.projectile_centre = ps.centre;
}

}  // namespace shatter::scene
