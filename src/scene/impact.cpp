// The impact helper (MPM paper Sec. 4.1, Fig. 4): the projectile touches the target at the
// impact point P = C_t + R n, where the surface normal n makes the impact angle alpha with the
// reversed velocity, so P is offset by R sin(alpha) perpendicular to the velocity (half the
// radius at 30 degrees, as in Nakamura & Fujiwara 1991).

#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "scene/parts.hpp"
#include "scene/ranges.hpp"

namespace shatter::scene {
namespace {

BodySpec* find_body(Scene& scene, const std::string& name) {
  for (auto& b : scene.bodies) {
    if (b.name == name) return &b;
  }
  return nullptr;
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
  if (ts == nullptr) {
    throw SceneError(in.where_target, "impact.target",
                     fmt::format("body '{}' must be a sphere for the impact helper", in.target));
  }
  const int a = scene.symmetry_axis;
  if (a >= 0 && ts->centre[a] != 0.0) {
    throw SceneError(target->where, fmt::format("body.{}.centre", in.target),
                     fmt::format("must lie on the symmetry plane {} = 0", "xyz"[a]));
  }
  auto& ps = std::get<Sphere>(projectile->shape.parts[0]);

  const double alpha = in.angle_deg * std::numbers::pi / 180.0;
  const Vec3 n = -std::cos(alpha) * in.direction + std::sin(alpha) * in.offset;
  const Vec3 impact_point = ts->centre + ts->radius * n;
  ps.centre = ts->centre + (ts->radius + ps.radius) * n - in.gap * in.direction;
  projectile->velocity = target->velocity + in.speed * in.direction;

  scene.impact.used = true;
  scene.impact.projectile = in.projectile;
  scene.impact.target = in.target;
  scene.impact.speed = in.speed;
  scene.impact.angle_deg = in.angle_deg;
  scene.impact.impact_point = impact_point;
  scene.impact.projectile_centre = ps.centre;
}

}  // namespace shatter::scene
