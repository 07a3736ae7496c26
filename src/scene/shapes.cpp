#include "shatter/scene/shapes.hpp"

#include "shatter/scene/boulders.hpp"
#include "shatter/scene/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace shatter::scene {
namespace {

template <class... Ts>
struct Overloaded : Ts... {
  using Ts::operator()...;
};
template <class... Ts>
Overloaded(Ts...) -> Overloaded<Ts...>;

}  // namespace

bool contains(const Primitive& s, const Vec3& p) {
  return std::visit(
      Overloaded{
          [&](const Sphere& b) { return (p - b.centre).squaredNorm() <= b.radius * b.radius; },
          [&](const Ellipsoid& b) {
            return ((p - b.centre).array() / b.semi_axes.array()).matrix().squaredNorm() <= 1.0;
          },
          [&](const Box& b) {
            return (p.array() >= b.lo.array()).all() && (p.array() <= b.hi.array()).all();
          },
          [&](const Cylinder& b) {
            const Vec3 d = p - b.centre;
            const double t = d.dot(b.axis);
            return std::abs(t) <= 0.5 * b.length &&
                   (d - t * b.axis).squaredNorm() <= b.radius * b.radius;
          },
          [&](const Mesh& b) { return b.solid->contains(p); }},
      s);
}

Bounds bounds(const Primitive& s) {
  return std::visit(
      Overloaded{[](const Sphere& b) {
                   return Bounds{b.centre.array() - b.radius, b.centre.array() + b.radius};
                 },
                 [](const Ellipsoid& b) {
                   return Bounds{b.centre - b.semi_axes, b.centre + b.semi_axes};
                 },
                 [](const Box& b) {
                   return Bounds{b.lo, b.hi};
                 },
                 [](const Cylinder& b) {
                   // Extent of a disc of radius r normal to a along axis i: r sqrt(1 - a_i^2).
                   const Vec3 disc = b.radius * (1.0 - b.axis.array().square()).max(0.0).sqrt();
                   const Vec3 half = 0.5 * b.length * b.axis.cwiseAbs() + disc;
                   return Bounds{b.centre - half, b.centre + half};
                 },
                 [](const Mesh& b) {
                   return Bounds{b.solid->lo(), b.solid->hi()};
                 }},
      s);
}

double volume(const Primitive& s) {
  constexpr double pi = std::numbers::pi;
  return std::visit(
      Overloaded{[](const Sphere& b) { return 4.0 / 3.0 * pi * b.radius * b.radius * b.radius; },
                 [](const Ellipsoid& b) { return 4.0 / 3.0 * pi * b.semi_axes.prod(); },
                 [](const Box& b) { return (b.hi - b.lo).prod(); },
                 [](const Cylinder& b) { return pi * b.radius * b.radius * b.length; },
                 [](const Mesh& b) { return b.solid->volume(); }},
      s);
}

bool Shape::contains(const Vec3& p) const {
  if (holes && holes->contains(p)) return false;
  if (only && !only->contains(p)) return false;
  return std::any_of(parts.begin(), parts.end(),
                     [&](const Primitive& s) { return scene::contains(s, p); });
}

Bounds Shape::bounds() const {
  Bounds b = scene::bounds(parts.front());
  for (const auto& s : parts) {
    const Bounds o = scene::bounds(s);
    b.lo = b.lo.cwiseMin(o.lo);
    b.hi = b.hi.cwiseMax(o.hi);
  }
  if (only) {
    const Bounds o = only->bounds();
    b.lo = b.lo.cwiseMax(o.lo);
    b.hi = b.hi.cwiseMin(o.hi);
  }
  return b;
}

std::optional<double> Shape::exact_volume() const {
  if (parts.size() != 1 || holes || only) return std::nullopt;
  return volume(parts.front());
}

}  // namespace shatter::scene
