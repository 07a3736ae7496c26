// The bodies of an axisymmetric (r-z) scene (solver.geometry = "axisymmetric", issue 31): each
// must be a body of revolution about the z axis, since the r-z engine models the half-plane
// y = 0, r >= 0 and revolves it (docs/validation-axisymmetric.md, "What is refused").

#include <cmath>
#include <string>
#include <variant>

#include <fmt/format.h>

#include "scene/parts.hpp"

namespace shatter::scene {
namespace {

// Off the axis by more than round-off of the body's size.
bool off_axis(const Vec3& c, double size) {
  return std::abs(c.x()) > 1e-12 * size || std::abs(c.y()) > 1e-12 * size;
}

// The key and the reason a primitive is not a body of revolution about z; empty when it is.
std::pair<std::string, std::string> not_revolved(const Primitive& part) {
  const std::string centred =
      "is off the axis: in r-z (solver.geometry = \"axisymmetric\") a "
      "body is centred on the z axis, x = y = 0";
  if (const auto* s = std::get_if<Sphere>(&part)) {
    if (off_axis(s->centre, s->radius)) return {"centre", centred};
  } else if (const auto* e = std::get_if<Ellipsoid>(&part)) {
    if (off_axis(e->centre, e->semi_axes.maxCoeff())) return {"centre", centred};
    if (e->semi_axes.x() != e->semi_axes.y()) {
      return {"semi_axes", "must have equal x and y semi-axes in r-z (a spheroid about z)"};
    }
  } else if (const auto* c = std::get_if<Cylinder>(&part)) {
    if (off_axis(c->centre, c->radius + c->length)) return {"centre", centred};
    if (std::abs(std::abs(c->axis.z()) - 1.0) > 1e-12) {
      return {"axis", "must be the z axis ([0, 0, 1]) in r-z"};
    }
  } else if (const auto* b = std::get_if<Box>(&part)) {
    // Its section in the r-z plane is taken and revolved: the cylinder of radius hi.x. Only a
    // box centred on the axis with a square x-y section has that reading without ambiguity.
    const Vec3 mid = 0.5 * (b->lo + b->hi), half = 0.5 * (b->hi - b->lo);
    if (off_axis(mid, half.maxCoeff())) return {"lo", centred};
    if (std::abs(half.x() - half.y()) > 1e-12 * half.maxCoeff()) {
      return {"hi",
              "must give a box with equal x and y extents in r-z (it is revolved into the "
              "cylinder of radius hi.x, its section in the r-z plane)"};
    }
  } else {
    return {"shape",
            "a triangle mesh cannot be revolved: r-z bodies are spheres, spheroids, "
            "cylinders along z and boxes centred on the axis"};
  }
  return {};
}

}  // namespace

void check_axisymmetric_body(const BodySpec& b) {
  const std::string key = "body." + b.name;
  for (const Primitive& part : b.shape.parts) {
    const auto [k, why] = not_revolved(part);
    if (!k.empty()) throw SceneError(b.where, key + "." + k, why);
  }
  if (!b.lattice_rotation.isIdentity(0.0)) {
    throw SceneError(b.where, key + ".lattice_rotation",
                     "has no meaning in r-z (the points lie on the r-z lattice of the grid)");
  }
  if (b.velocity.x() != 0.0 || b.velocity.y() != 0.0) {
    throw SceneError(b.where, key + ".velocity",
                     fmt::format("must lie along z in r-z (got [{}, {}, {}] m/s): an impact off "
                                 "the axis is not axisymmetric",
                                 b.velocity.x(), b.velocity.y(), b.velocity.z()));
  }
  if (b.driven) {
    throw SceneError(b.where, key + ".driven", "driven bodies are not verified in r-z yet");
  }
  if (b.flaws && b.flaws->scheme == "benz_asphaug") {
    // BA95's draw places N ln N flaws on equal points one by one; an r-z ring stands for many 3-D
    // points, which that draw does not know. The resolution-independent scheme gives each ring
    // the flaws of one 3-D point of its size (src/fracture/flaws.cpp) and is allowed.
    throw SceneError(b.where, key + ".damage.explicit_flaws",
                     "explicit flaws (BA95's draw) are not supported in r-z: a point is a ring; "
                     "use explicit_flaws = 0 (the resolution-independent flaws)");
  }
}

}  // namespace shatter::scene
