// The axisymmetric (r-z) lattice fill (include/shatter/scene/lattice.hpp): points in the
// half-plane y = 0, r > 0, each the ring its cell sweeps (Sulsky & Schreyer 1996, CMAME 139:
// a point's mass and volume are those of its ring, V_p = 2 pi r_p A_p).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "shatter/scene/lattice.hpp"

namespace shatter::scene {
namespace {

// Sub-samples per axis in a cell that straddles the surface (as the 3-D fill's kSub).
constexpr int kSub = 6;

struct Range2 {
  std::int64_t i_hi, k_lo, k_hi;  // i in [0, i_hi), k in [k_lo, k_hi)
};

Range2 index_range(const Shape& shape, double s) {
  const Bounds b = shape.bounds();
  const double r_max =
      std::max({std::abs(b.lo.x()), std::abs(b.hi.x()), std::abs(b.lo.y()), std::abs(b.hi.y())});
  return {static_cast<std::int64_t>(std::ceil(r_max / s)) + 1,
          static_cast<std::int64_t>(std::floor(b.lo.z() / s)) - 1,
          static_cast<std::int64_t>(std::ceil(b.hi.z() / s)) + 1};
}

// The ring volume of the part of cell (i, k) inside the shape: 2 pi int r dA over the inside
// sub-samples (exact, 2 pi r_c s^2, for a cell wholly inside).
double ring_volume(const Shape& shape, double s, std::int64_t i, std::int64_t k) {
  const double d = s / kSub;
  double v = 0.0;
  for (int a = 0; a < kSub; ++a) {
    for (int c = 0; c < kSub; ++c) {
      const double r = i * s + (a + 0.5) * d, z = k * s + (c + 0.5) * d;
      if (shape.contains(Vec3(r, 0.0, z))) v += 2.0 * std::numbers::pi * r * d * d;
    }
  }
  return v;
}

}  // namespace

void for_each_lattice_point_rz(const Shape& shape, double s,
                               const std::function<void(const Vec3&)>& visit) {
  const Range2 n = index_range(shape, s);
  for (std::int64_t k = n.k_lo; k < n.k_hi; ++k) {
    for (std::int64_t i = 0; i < n.i_hi; ++i) {
      const Vec3 p((i + 0.5) * s, 0.0, (k + 0.5) * s);
      if (shape.contains(p)) visit(p);
    }
  }
}

LatticeFill fill_lattice_rz(const Shape& shape, double s) {
  const Range2 n = index_range(shape, s);
  LatticeFill fill;
  double nominal = 0.0;
  for (std::int64_t k = n.k_lo; k < n.k_hi; ++k) {
    for (std::int64_t i = 0; i < n.i_hi; ++i) {
      const Vec3 p((i + 0.5) * s, 0.0, (k + 0.5) * s);
      const bool in = shape.contains(p);
      // Corners of the cell: a cell with all four inside and its centre inside is whole.
      int corners = 0;
      for (int c = 0; c < 4; ++c) {
        corners += shape.contains(Vec3((i + (c & 1)) * s, 0.0, (k + (c >> 1)) * s)) ? 1 : 0;
      }
      const double whole = 2.0 * std::numbers::pi * p.x() * s * s;
      if (corners == 4 && in) {
        fill.volume += whole;
      } else if (corners > 0 || in) {
        fill.volume += ring_volume(shape, s, i, k);
      }
      if (in) {
        fill.points.push_back(p);
        fill.volumes.push_back(whole);
        nominal += whole;
      }
    }
  }
  // Volume-weighted, as the 3-D fill: the body has its true mass whatever the resolution.
  if (nominal > 0.0) {
    for (double& v : fill.volumes) v *= fill.volume / nominal;
  }
  return fill;
}

}  // namespace shatter::scene
