#include "shatter/scene/lattice.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

namespace shatter::scene {
namespace {

// Sub-samples per axis in a lattice cell that straddles the surface: 6^3 samples put the volume
// error of a sphere of 4 cells radius below 0.1 %.
constexpr int kSub = 6;

// The shape seen from the lattice's own frame: q is inside when R q is inside the shape.
struct Turned {
  const Shape& shape;
  const Eigen::Matrix3d& rotation;
  bool contains(const Vec3& q) const { return shape.contains(rotation * q); }
  // Bounds in the lattice frame: the shape's box turned back by R^T (R is orthonormal).
  Bounds bounds() const {
    const Bounds b = shape.bounds();
    Bounds t{Vec3::Constant(std::numeric_limits<double>::infinity()),
             Vec3::Constant(-std::numeric_limits<double>::infinity())};
    for (int c = 0; c < 8; ++c) {
      const Vec3 corner((c & 1) ? b.hi.x() : b.lo.x(), (c & 2) ? b.hi.y() : b.lo.y(),
                        (c & 4) ? b.hi.z() : b.lo.z());
      const Vec3 q = rotation.transpose() * corner;
      t.lo = t.lo.cwiseMin(q);
      t.hi = t.hi.cwiseMax(q);
    }
    return t;
  }
};

double cell_fraction(const Turned& shape, const Vec3& centre, double s) {
  int inside = 0;
  for (int a = 0; a < kSub; ++a) {
    for (int b = 0; b < kSub; ++b) {
      for (int c = 0; c < kSub; ++c) {
        const Vec3 q = centre + s * (Vec3(a, b, c).array() + 0.5 - 0.5 * kSub).matrix() / kSub;
        inside += shape.contains(q) ? 1 : 0;
      }
    }
  }
  return static_cast<double>(inside) / (kSub * kSub * kSub);
}

// Lattice index range covering the bounds, one cell of margin for the corner tests.
void index_range(const Turned& shape, double s, int clip_axis, std::array<std::int64_t, 3>& lo,
                 std::array<std::int64_t, 3>& hi) {
  const Bounds b = shape.bounds();
  for (int a = 0; a < 3; ++a) {
    lo[a] = static_cast<std::int64_t>(std::floor(b.lo[a] / s)) - 1;
    hi[a] = static_cast<std::int64_t>(std::ceil(b.hi[a] / s)) + 1;
    if (a == clip_axis) lo[a] = std::max<std::int64_t>(lo[a], 0);
  }
}

}  // namespace

void for_each_lattice_point(const Shape& body, double s, int clip_axis,
                            const std::function<void(const Vec3&)>& visit,
                            const Eigen::Matrix3d& rotation) {
  const Turned shape{body, rotation};
  std::array<std::int64_t, 3> lo{}, hi{};
  index_range(shape, s, clip_axis, lo, hi);
  for (std::int64_t k = lo[2]; k < hi[2]; ++k) {
    for (std::int64_t j = lo[1]; j < hi[1]; ++j) {
      for (std::int64_t i = lo[0]; i < hi[0]; ++i) {
        const Vec3 centre((i + 0.5) * s, (j + 0.5) * s, (k + 0.5) * s);
        if (shape.contains(centre)) visit(rotation * centre);
      }
    }
  }
}

LatticeCount count_lattice(const Shape& shape, double s, int clip_axis,
                           const Eigen::Matrix3d& rotation) {
  LatticeCount c;
  for_each_lattice_point(
      shape, s, clip_axis,
      [&](const Vec3& p) {
        ++c.points;
        c.lo = c.lo.cwiseMin(p);
        c.hi = c.hi.cwiseMax(p);
      },
      rotation);
  return c;
}

LatticeFill fill_lattice(const Shape& body, double s, int clip_axis,
                         const Eigen::Matrix3d& rotation) {
  const Turned shape{body, rotation};
  std::array<std::int64_t, 3> lo{}, hi{};
  index_range(shape, s, clip_axis, lo, hi);
  // Inside status at lattice cell corners (points k s), shared by neighbouring cells.
  const std::int64_t nx = hi[0] - lo[0] + 1, ny = hi[1] - lo[1] + 1, nz = hi[2] - lo[2] + 1;
  std::vector<std::uint8_t> corner(static_cast<std::size_t>(nx * ny * nz));
  auto corner_at = [&](std::int64_t i, std::int64_t j, std::int64_t k) -> std::uint8_t& {
    return corner[static_cast<std::size_t>(((k - lo[2]) * ny + (j - lo[1])) * nx + (i - lo[0]))];
  };
  for (std::int64_t k = lo[2]; k <= hi[2]; ++k) {
    for (std::int64_t j = lo[1]; j <= hi[1]; ++j) {
      for (std::int64_t i = lo[0]; i <= hi[0]; ++i) {
        corner_at(i, j, k) = shape.contains(Vec3(i * s, j * s, k * s)) ? 1 : 0;
      }
    }
  }

  LatticeFill fill;
  const double cell_volume = s * s * s;
  for (std::int64_t k = lo[2]; k < hi[2]; ++k) {
    for (std::int64_t j = lo[1]; j < hi[1]; ++j) {
      for (std::int64_t i = lo[0]; i < hi[0]; ++i) {
        const Vec3 centre((i + 0.5) * s, (j + 0.5) * s, (k + 0.5) * s);
        const bool in = shape.contains(centre);
        if (in) fill.points.push_back(rotation * centre);
        int corners = 0;
        for (int c = 0; c < 8; ++c)
          corners += corner_at(i + (c & 1), j + ((c >> 1) & 1), k + (c >> 2));
        if (corners == 8 && in) {
          fill.volume += cell_volume;
        } else if (corners > 0 || in) {
          fill.volume += cell_volume * cell_fraction(shape, centre, s);
        }
      }
    }
  }
  return fill;
}

}  // namespace shatter::scene
