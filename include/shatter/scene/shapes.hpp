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

// A body's shape: the union of its parts (one part for a plain primitive).
struct Shape {
  std::vector<Primitive> parts;

  bool contains(const Vec3& p) const;
  Bounds bounds() const;
  // Exact volume of a single primitive; none for a union (parts may overlap).
  std::optional<double> exact_volume() const;
};

}  // namespace shatter::scene
