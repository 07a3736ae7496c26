#pragma once
// Body geometry: primitives (sphere, ellipsoid, box, cylinder, closed triangle mesh) and unions
// of them, with an inside test, bounds and — for single primitives — the exact volume.

#include <memory>
#include <optional>
#include <variant>
#include <vector>

#include <Eigen/Core>

namespace shatter::scene {

using Vec3 = Eigen::Vector3d;

struct Sphere {
  Vec3 centre = Vec3::Zero();
  double radius = 0.0;
};
// Axis-aligned ellipsoid.
struct Ellipsoid {
  Vec3 centre = Vec3::Zero();
  Vec3 semi_axes = Vec3::Zero();
};
// Axis-aligned box.
struct Box {
  Vec3 lo = Vec3::Zero();
  Vec3 hi = Vec3::Zero();
};
// Circular cylinder of the given length along `axis` (unit vector), centred at `centre`.
struct Cylinder {
  Vec3 centre = Vec3::Zero();
  Vec3 axis = Vec3::UnitZ();
  double radius = 0.0;
  double length = 0.0;
};

class MeshSolid;
// A closed triangle mesh, already scaled, rotated and placed (include/shatter/scene/mesh.hpp).
struct Mesh {
  std::shared_ptr<const MeshSolid> solid;
};

using Primitive = std::variant<Sphere, Ellipsoid, Box, Cylinder, Mesh>;

class SphereSet;  // include/shatter/scene/boulders.hpp

struct Bounds {
  Vec3 lo = Vec3::Zero();
  Vec3 hi = Vec3::Zero();
  bool intersects(const Bounds& o) const {
    return (lo.array() <= o.hi.array()).all() && (o.lo.array() <= hi.array()).all();
  }
};

bool contains(const Primitive& s, const Vec3& p);
Bounds bounds(const Primitive& s);
double volume(const Primitive& s);

// A body's shape: the union of its parts (one part for a plain primitive). A boulder field
// (include/shatter/scene/boulders.hpp) cuts its spheres out of its host (`holes`) and makes the
// boulder body the host's parts restricted to the spheres (`only`), so that the two bodies share
// the host's lattice and split its points exactly.
struct Shape {
  Shape() = default;
  // A primitive or a union of parts: Shape{{Sphere{...}}}.
  Shape(std::vector<Primitive> p) : parts(std::move(p)) {}  // NOLINT(google-explicit-constructor)

  std::vector<Primitive> parts;
  std::shared_ptr<const SphereSet> holes;  // points inside one of these are outside
  std::shared_ptr<const SphereSet> only;   // when set, points outside all of these are outside

  bool contains(const Vec3& p) const;
  Bounds bounds() const;
  // Exact volume of a single primitive; none for a union (parts may overlap) or with boulders.
  std::optional<double> exact_volume() const;
};

}  // namespace shatter::scene
