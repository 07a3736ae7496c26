// The scene's [beta] table (issue 32): the momentum enhancement of a kinetic impact, measured in
// the time series (include/shatter/fracture/beta.hpp; docs/validation-dart.md).

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "scene/parts.hpp"
#include "shatter/io/suggest.hpp"

namespace shatter::scene {
namespace {

// The body id of the body named by `key` (bodies are numbered in the order they are read).
std::int64_t body_id(const Reader& r, std::string_view key, const std::string& name,
                     const Scene& scene) {
  std::vector<std::string> names;
  for (const auto& b : scene.bodies) names.push_back(b.name);
  const auto it = std::find(names.begin(), names.end(), name);
  if (it == names.end()) {
    r.fail(key, fmt::format("no body '{}'{} (bodies: {})", name, io::did_you_mean(name, names),
                            fmt::join(names, ", ")));
  }
  return it - names.begin();
}

Vec3 unit(const Reader& r, std::string_view key, const Vec3& v) {
  if (!(v.norm() > 0.0)) r.fail(key, "must not be the zero vector");
  return v.normalized();
}

}  // namespace

void read_beta(Reader& root, Scene& scene) {
  toml::table* t = root.subtable("beta");
  if (t == nullptr) return;
  Reader r(*t, "beta", root.where("beta"));
  r.allow({"impactor", "surface", "normal", "escape_speed"});
  r.reject_unknown();
  const bool helper = scene.impact.used;
  BetaSpec spec;
  const std::string impactor =
      helper ? r.string("impactor", scene.impact.projectile) : r.string("impactor");
  r.note_default("impactor", "impact.projectile; *required* without [impact]");
  spec.impactor = body_id(r, "impactor", impactor, scene);
  const Vec3 v = scene.bodies[static_cast<std::size_t>(spec.impactor)].velocity;
  if (!(v.norm() > 0.0)) {
    r.fail("impactor", fmt::format("body '{}' has no velocity: beta needs the impactor's "
                                   "momentum m U before the impact",
                                   impactor));
  }
  spec.direction = v.normalized();
  spec.impact_speed = v.norm();
  spec.surface_point = helper ? r.vec3("surface", scene.impact.impact_point) : r.vec3("surface");
  r.note_default("surface", "impact point of [impact]; *required* without it");
  r.note_range("surface", "a point of the pre-impact target surface (the control plane)", "m");
  spec.normal = unit(r, "normal", r.vec3("normal", -spec.direction));
  r.note_default("normal", "minus the impactor's velocity direction");
  if (!(spec.normal.dot(spec.direction) < 0.0)) {
    r.fail("normal", "must point out of the target, against the impactor's velocity");
  }
  if (scene.solver.geometry == Geometry::axisymmetric &&
      std::abs(std::abs(spec.normal.z()) - 1.0) > 1e-12) {
    r.fail("normal", "must be along z in r-z geometry (the axis of revolution)");
  }
  spec.escape_speed = r.non_negative("escape_speed", r.number("escape_speed", 0.0));
  r.note_range("escape_speed", "0 = no speed criterion", "m/s");
  scene.beta = spec;
}

}  // namespace shatter::scene
