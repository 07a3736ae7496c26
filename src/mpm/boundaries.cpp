#include "shatter/mpm/boundaries.hpp"

#include "shatter/parallel/exact_sum.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

namespace shatter::mpm {
namespace {

constexpr const char* kFaceNames[6] = {"-x", "+x", "-y", "+y", "-z", "+z"};

// The node arrays a mirror pass touches (mirror_impl).
struct MirrorArrays {
  double* mom[3];
  double* force[3];
  // Mass gradients of body copies (contact normals): mass is even under the mirror, so the
  // normal component of its gradient is odd, the tangential ones even.
  double* grad[3];
  std::size_t g0;  // first body-copy node (the gradients are indexed from there)
  bool force_too;  // mass and force mirrored as well as momentum
  bool grads;      // the body copies' mass gradients too
};

MirrorArrays mirror_arrays(SparseGrid& grid, Boundaries::MirrorMode mode) {
  auto& N = grid.nodes();
  const bool force_too = mode == Boundaries::kMassMomentumForce;
  return {{N.px.data(), N.py.data(), N.pz.data()},
          {N.fx.data(), N.fy.data(), N.fz.data()},
          {N.gx.data(), N.gy.data(), N.gz.data()},
          grid.shared_blocks() * SparseGrid::kBlockNodes,
          force_too,
          force_too && grid.has_copies()};
}

// Visits the ghost nodes within a stencil's reach (3 nodes) of plane pl together with their
// partner nodes: pass(ghost, partner), global node indices. On a symmetry plane the mirror
// cancels the normal component; a ghost whose partner no particle reaches has nothing to mirror,
// and beyond a fixed wall the image of empty space is at rest.
template <class Pass>
void for_ghosts(const SparseGrid& grid, const Boundaries::Plane& pl, const MirrorArrays& a,
                Pass&& pass) {
  const auto node = [](std::size_t b, int l) {
    return b * SparseGrid::kBlockNodes + static_cast<std::size_t>(l);
  };
  walk_ghosts(
      pl, grid.blocks(), [&](std::size_t b) { return grid.coord(static_cast<std::uint32_t>(b)); },
      // a block where bodies meet: its field lives in the body copies
      [&](std::size_t b) { return grid.meets(static_cast<std::uint32_t>(b)); },
      // the partner in the same velocity field (the same body's copy where bodies meet)
      [&](std::size_t b, std::uint64_t key) {
        return grid.find_like(static_cast<std::uint32_t>(b), key);
      },
      [&](std::size_t b, int l) {
        // On the plane the mirror cancels the normal component.
        const std::size_t i = node(b, l);
        a.mom[pl.axis][i] = 0.0;
        if (a.force_too) a.force[pl.axis][i] = 0.0;
        if (a.grads && i >= a.g0) a.grad[pl.axis][i - a.g0] = 0.0;
      },
      [&](std::size_t b, int l) {
        const std::size_t i = node(b, l);
        a.mom[0][i] = a.mom[1][i] = a.mom[2][i] = 0.0;
        if (a.force_too) a.force[0][i] = a.force[1][i] = a.force[2][i] = 0.0;
      },
      [&](std::size_t b, int l, std::size_t pb, int pl_) { pass(node(b, l), node(pb, pl_)); });
}

}  // namespace

Boundaries::Boundaries(const Domain& domain, double cell_size) {
  for (int f = 0; f < 6; ++f) {
    const BoundaryKind kind = domain.faces[static_cast<std::size_t>(f)];
    if (kind == BoundaryKind::none) continue;
    const int axis = f / 2;
    const int side = (f % 2 == 0) ? -1 : 1;
    const double at = side < 0 ? domain.lo[axis] : domain.hi[axis];
    const double k = at / cell_size;
    if (!std::isfinite(k) || std::abs(k - std::round(k)) > 1e-6) {
      throw std::invalid_argument(fmt::format(
          "domain face {} ({}) at {} m is not on a grid plane: it must be a multiple of the cell "
          "size {} m",
          kFaceNames[f], name_of(kind), at, cell_size));
    }
    planes_[static_cast<std::size_t>(count_++)] = {axis, side, std::llround(k), kind};
    const auto a = static_cast<std::size_t>(axis);
    if (kind == BoundaryKind::outflow) {
      (side < 0 ? out_lo_ : out_hi_)[a] = at;
    } else if (side < 0) {  // constrain_planes acts on nodes i <= index of a low face
      free_lo_[a] = std::max<std::int64_t>(free_lo_[a], std::llround(k) + 1);
    } else {
      free_hi_[a] = std::min<std::int64_t>(free_hi_[a], std::llround(k) - 1);
    }
  }
}

bool Boundaries::has_outflow() const {
  for (int k = 0; k < count_; ++k) {
    if (planes_[static_cast<std::size_t>(k)].kind == BoundaryKind::outflow) return true;
  }
  return false;
}

void Boundaries::constrain_planes(const std::int64_t node[3], double& x, double& y,
                                  double& z) const {
  double* v[3] = {&x, &y, &z};
  for (int k = 0; k < count_; ++k) {
    const Plane& pl = planes_[static_cast<std::size_t>(k)];
    const std::int64_t i = node[pl.axis];
    const bool on_or_beyond = pl.side < 0 ? i <= pl.index : i >= pl.index;
    if (!on_or_beyond) continue;
    switch (pl.kind) {
      // Fixed: the plane is at rest; nodes beyond it hold the odd mirror image (see mirror()).
      case BoundaryKind::fixed:
        if (i == pl.index) x = y = z = 0.0;
        break;
      case BoundaryKind::slip:
        *v[pl.axis] = 0.0;
        break;
      // Symmetry: only the plane itself is constrained; nodes beyond it hold the mirror image.
      case BoundaryKind::symmetry:
        if (i == pl.index) *v[pl.axis] = 0.0;
        break;
      case BoundaryKind::none:
      case BoundaryKind::outflow:
        break;
    }
  }
}

void Boundaries::mirror_ghosts(SparseGrid& grid) const {
  mirror_impl(grid, kMassMomentumForce, false);
}

void Boundaries::mirror(SparseGrid& grid, MirrorMode mode) const {
  mirror_impl(grid, mode, true);
}

void Boundaries::mirror_impl(SparseGrid& grid, MirrorMode mode, bool fold) const {
  auto& N = grid.nodes();
  for (int k = 0; k < count_; ++k) {
    const Plane& pl = planes_[static_cast<std::size_t>(k)];
    if (pl.kind != BoundaryKind::symmetry && pl.kind != BoundaryKind::fixed) continue;
    // Symmetry: the images of the particles across the plane are folded in; the normal
    // component is odd, the tangential ones even. Fixed: nothing lies beyond a wall, but the
    // field there must be the odd image v(-x) = -v(x) so that the velocity passes through zero at
    // the wall with its slope intact; zeroing the ghost nodes would also clamp the strain rate
    // at the wall and makes the quadratic B-spline first order (docs/verification.md).
    const bool fixed = pl.kind == BoundaryKind::fixed;
    auto sign = [&](int d) { return fixed || d == pl.axis ? -1.0 : 1.0; };
    const MirrorArrays a = mirror_arrays(grid, mode);
    auto gsign = [&](int d) { return d == pl.axis ? -1.0 : 1.0; };
    // Fold: what the mirror images would add to the partner nodes.
    if (fold)
      for_ghosts(grid, pl, a, [&](std::size_t ghost, std::size_t partner) {
        if (a.force_too) N.mass[partner] += N.mass[ghost];
        for (int d = 0; d < 3; ++d) {
          a.mom[d][partner] += sign(d) * a.mom[d][ghost];
          if (a.force_too) a.force[d][partner] += sign(d) * a.force[d][ghost];
          if (a.grads && ghost >= a.g0 && partner >= a.g0) {
            a.grad[d][partner - a.g0] += gsign(d) * a.grad[d][ghost - a.g0];
          }
        }
      });
    // Ghosts become the mirror image of the completed field.
    for_ghosts(grid, pl, a, [&](std::size_t ghost, std::size_t partner) {
      if (a.force_too) N.mass[ghost] = N.mass[partner];
      for (int d = 0; d < 3; ++d) {
        a.mom[d][ghost] = sign(d) * a.mom[d][partner];
        if (a.force_too) a.force[d][ghost] = sign(d) * a.force[d][partner];
        if (a.grads && ghost >= a.g0 && partner >= a.g0) {
          a.grad[d][ghost - a.g0] = gsign(d) * a.grad[d][partner - a.g0];
        }
      }
    });
  }
}

namespace {

// The block-parallel pass integrate() and velocities() share: visit(i, c, l, count, removed) at
// every node (i its index, c its block's coordinates, l its local index, count whether its block
// is counted), each adding the energy it removes to `removed`, an exact sum (parallel::ExactSum),
// so that the total does not depend on the block order.
template <class Visit>
parallel::ExactSum sum_over_nodes(const SparseGrid& grid, const std::vector<std::uint8_t>* counted,
                                  Visit&& visit) {
  return tbb::parallel_reduce(
      tbb::blocked_range<std::uint32_t>(0, static_cast<std::uint32_t>(grid.blocks()), 16),
      parallel::ExactSum{},
      [&](const tbb::blocked_range<std::uint32_t>& r, parallel::ExactSum removed) {
        for (std::uint32_t b = r.begin(); b < r.end(); ++b) {
          const bool count = counted == nullptr || (*counted)[b] != 0;
          const SparseGrid::Coord c = grid.coord(b);
          for (int l = 0; l < SparseGrid::kBlockNodes; ++l) {
            const std::size_t i =
                std::size_t{b} * SparseGrid::kBlockNodes + static_cast<std::size_t>(l);
            visit(i, c, l, count, removed);
          }
        }
        return removed;
      },
      [](parallel::ExactSum a, const parallel::ExactSum& b) {
        a.add(b);
        return a;
      });
}

// Global index of node l of the block at c.
void global_node(const SparseGrid::Coord& c, int l, std::int64_t g[3]) {
  g[0] = std::int64_t{c.x} * 4 + l / 16;
  g[1] = std::int64_t{c.y} * 4 + (l / 4) % 4;
  g[2] = std::int64_t{c.z} * 4 + l % 4;
}

// The kinetic energy a constraint removes from momentum p of nodal mass M (before minus after).
double removed_energy(double before, double px, double py, double pz, double M) {
  return 0.5 * (before - (px * px + py * py + pz * pz)) / M;
}

}  // namespace

double Boundaries::integrate(SparseGrid& grid, const Vec3& gravity, double dt, double empty_mass,
                             const std::vector<std::uint8_t>* counted,
                             parallel::ExactSum* exact) const {
  auto& N = grid.nodes();
  const bool constrained = count_ > 0;
  parallel::ExactSum total =
      sum_over_nodes(grid, counted,
                     [&](std::size_t i, const SparseGrid::Coord& c, int l, bool count,
                         parallel::ExactSum& removed) {
                       const double M = N.mass[i];
                       if (M <= empty_mass) {
                         N.px[i] = N.py[i] = N.pz[i] = N.fx[i] = N.fy[i] = N.fz[i] = 0.0;
                         return;
                       }
                       double fx = N.fx[i] + M * gravity.x();  // Eq. 30, body force
                       double fy = N.fy[i] + M * gravity.y();
                       double fz = N.fz[i] + M * gravity.z();
                       double px = N.px[i], py = N.py[i], pz = N.pz[i];
                       if (constrained) {
                         std::int64_t g[3];
                         global_node(c, l, g);
                         const double before = px * px + py * py + pz * pz;
                         constrain(g, px, py, pz);  // step 2
                         constrain(g, fx, fy, fz);  // step 3
                         if (count) removed.add(removed_energy(before, px, py, pz, M));
                       }
                       px += fx * dt;  // step 4, Eq. 27
                       py += fy * dt;
                       pz += fz * dt;
                       const double inv_m = 1.0 / M;
                       N.fx[i] = fx * inv_m;
                       N.fy[i] = fy * inv_m;
                       N.fz[i] = fz * inv_m;
                       N.px[i] = px * inv_m;
                       N.py[i] = py * inv_m;
                       N.pz[i] = pz * inv_m;
                     });
  if (exact != nullptr) *exact = total;
  return total.value();
}

double Boundaries::velocities(SparseGrid& grid, double empty_mass,
                              const std::vector<std::uint8_t>* counted) const {
  auto& N = grid.nodes();
  const bool constrained = count_ > 0;
  return sum_over_nodes(grid, counted,
                        [&](std::size_t i, const SparseGrid::Coord& c, int l, bool count,
                            parallel::ExactSum& removed) {
                          const double M = N.mass[i];
                          if (M <= empty_mass) {
                            N.px[i] = N.py[i] = N.pz[i] = 0.0;
                            return;
                          }
                          double px = N.px[i], py = N.py[i], pz = N.pz[i];
                          if (constrained) {
                            std::int64_t g[3];
                            global_node(c, l, g);
                            const double before = px * px + py * py + pz * pz;
                            constrain(g, px, py, pz);
                            if (count) removed.add(removed_energy(before, px, py, pz, M));
                          }
                          const double inv_m = 1.0 / M;
                          N.px[i] = px * inv_m;
                          N.py[i] = py * inv_m;
                          N.pz[i] = pz * inv_m;
                        })
      .value();
}

}  // namespace shatter::mpm
