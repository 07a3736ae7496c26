#pragma once
// Boundary conditions on grid planes (ISSUE engine item 7) and the nodal momentum update
// (App. A.2 steps 2-4 and 6-7).

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "shatter/core/config.hpp"
#include "shatter/grid/sparse_grid.hpp"
#include "shatter/parallel/exact_sum.hpp"

namespace shatter::mpm {

class Boundaries {
 public:
  // Throws std::invalid_argument if a face with a condition does not lie on a grid plane.
  Boundaries(const Domain& domain, double cell_size);

  enum MirrorMode { kMassMomentumForce, kMomentum };

  bool has_outflow() const;
  // Past an outflow face: below the low face's coordinate or above the high face's, on each
  // axis with an outflow face there (the bounds of the other faces are -inf / +inf, which no
  // coordinate passes, NaN included). Inline and without a branch per face: it runs once per
  // point in G2P and in the outflow stage (2.0 % of the laboratory impact out of line).
  bool outside_outflow(const Vec3& x) const { return outside_outflow(x[0], x[1], x[2]); }
  bool outside_outflow(double x, double y, double z) const {
    return (x < out_lo_[0]) | (x > out_hi_[0]) | (y < out_lo_[1]) | (y > out_hi_[1]) |
           (z < out_lo_[2]) | (z > out_hi_[2]);
  }

  // Symmetry planes: makes the nodal fields mirror-symmetric about each plane. Contributions that
  // particles made to nodes beyond the plane are what their mirror images would have made to the
  // partner nodes, so they are folded in (normal components with flipped sign); the ghost nodes
  // then take the mirror of the completed field. A half model then sees exactly the field of the
  // full symmetric model.
  void mirror(SparseGrid& grid, MirrorMode mode) const;
  // Only the second half of mirror(): ghost nodes take the image of their partners' p* and f*
  // arrays (velocity and acceleration after integrate()). Used after the contact correction,
  // which treats a ghost and its partner separately (their blocks need not meet the same bodies).
  void mirror_ghosts(SparseGrid& grid) const;

  // Steps 2-4: gravity, constraints on momentum and force, P^{n+1/2} = P^{n-1/2} + F dt^n
  // (Eq. 27). Leaves the nodal acceleration F/M in f* and velocity P^{n+1/2}/M in p*. Returns the
  // kinetic energy the constraints removed.
  // The kinetic energy the constraints removed is summed exactly (parallel::ExactSum), so it does
  // not depend on the block order; `counted` (one flag per block), when given, limits the sum
  // to the blocks this rank owns (ghost blocks hold copies of other ranks' nodes).
  // `exact`, when given, also receives the exact sum (to be combined across ranks).
  double integrate(SparseGrid& grid, const Vec3& gravity, double dt, double empty_mass,
                   const std::vector<std::uint8_t>* counted = nullptr,
                   parallel::ExactSum* exact = nullptr) const;

  // Steps 6-7: constraints on the remapped momentum, then v_I = P_I / M_I in p*. Returns the
  // nodal kinetic energy the constraints removed (a diagnostic: no particle velocity changes).
  double velocities(SparseGrid& grid, double empty_mass,
                    const std::vector<std::uint8_t>* counted = nullptr) const;

  bool constrained() const { return count_ > 0; }

  struct Plane {
    int axis;
    int side;            // -1: the domain's low face (material at i >= index), +1: high face
    std::int64_t index;  // node index of the plane along axis
    BoundaryKind kind;
  };
  std::span<const Plane> planes() const {
    return {planes_.data(), static_cast<std::size_t>(count_)};
  }

  // mirror() on blocks that are not one SparseGrid: the halo owner's blocks on several ranks
  // (docs/mpi.md), with the same operations in the same order, so the same bits. `blocks`
  // provides size(), coord(i) (SparseGrid::Coord), find(key) (index or -1) and
  // field(i, f) (64 nodes of field f: 0 mass, 1-3 momentum, 4-6 force). No body copies.
  template <class Blocks>
  void mirror_blocks(Blocks& blocks, MirrorMode mode) const;
  // Zeroes the constrained components of (x, y, z) at global node `node` (steps 2-3). A node
  // that no plane is on or beyond (all of them but the layers at the faces) returns at an
  // inline test: the grid update calls this for every node.
  void constrain(const std::int64_t node[3], double& x, double& y, double& z) const {
    if ((node[0] >= free_lo_[0]) & (node[0] <= free_hi_[0]) & (node[1] >= free_lo_[1]) &
        (node[1] <= free_hi_[1]) & (node[2] >= free_lo_[2]) & (node[2] <= free_hi_[2])) {
      return;
    }
    constrain_planes(node, x, y, z);
  }

 private:
  void mirror_impl(SparseGrid& grid, MirrorMode mode, bool fold) const;
  void constrain_planes(const std::int64_t node[3], double& x, double& y, double& z) const;
  std::array<Plane, 6> planes_{};
  int count_ = 0;
  // The outflow faces' coordinates per axis; -inf / +inf where that face is not an outflow face.
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  std::array<double, 3> out_lo_{-kInf, -kInf, -kInf};
  std::array<double, 3> out_hi_{kInf, kInf, kInf};
  // Per axis, the node indices that no constraining plane (fixed, slip, symmetry) is on or
  // beyond: constrain() leaves those nodes as they are.
  static constexpr std::int64_t kLowest = std::numeric_limits<std::int64_t>::min();
  static constexpr std::int64_t kHighest = std::numeric_limits<std::int64_t>::max();
  std::array<std::int64_t, 3> free_lo_{kLowest, kLowest, kLowest};
  std::array<std::int64_t, 3> free_hi_{kHighest, kHighest, kHighest};
};

// The ghost walk both mirror passes share (mirror() on a SparseGrid, mirror_blocks on the halo
// owner's blocks), so both visit the same nodes in the same order. For the blocks 0..nblocks-1
// within a stencil's reach (3 nodes) of plane pl, skip(b) aside: on_plane(b, l) at a node on a
// symmetry plane; for a ghost node beyond the plane, its partner block through
// partner_block(b, key) (index or -1), then missing(b, l) on a fixed wall when there is none, or
// pass(b, l, partner block, partner's local node).
template <class CoordOf, class Skip, class PartnerBlock, class OnPlane, class Missing, class Pass>
void walk_ghosts(const Boundaries::Plane& pl, std::size_t nblocks, CoordOf&& coord_of, Skip&& skip,
                 PartnerBlock&& partner_block, OnPlane&& on_plane, Missing&& missing, Pass&& pass) {
  constexpr int B = SparseGrid::kBlock;
  const bool fixed = pl.kind == BoundaryKind::fixed;
  for (std::size_t b = 0; b < nblocks; ++b) {
    if (skip(b)) continue;
    const SparseGrid::Coord c = coord_of(b);
    const std::int64_t bc[3] = {c.x, c.y, c.z};
    const std::int64_t lo = bc[pl.axis] * B;
    if (lo + B - 1 < pl.index - 3 || lo > pl.index + 3) continue;
    for (int l = 0; l < SparseGrid::kBlockNodes; ++l) {
      const int loc[3] = {l / (B * B), (l / B) % B, l % B};
      std::int64_t g[3];
      for (int d = 0; d < 3; ++d) g[d] = bc[d] * B + loc[d];
      const std::int64_t i = g[pl.axis];
      const bool ghost = pl.side < 0 ? i < pl.index : i > pl.index;
      if (i == pl.index && !fixed) {
        on_plane(b, l);
        continue;
      }
      if (!ghost || std::abs(i - pl.index) > 3) continue;
      std::int64_t q[3] = {g[0], g[1], g[2]};
      q[pl.axis] = 2 * pl.index - i;
      const std::int64_t pb = partner_block(b, SparseGrid::key(q[0] >> 2, q[1] >> 2, q[2] >> 2));
      if (pb < 0) {
        if (fixed) missing(b, l);
        continue;
      }
      pass(b, l, static_cast<std::size_t>(pb),
           SparseGrid::local(static_cast<int>(q[0] & 3), static_cast<int>(q[1] & 3),
                             static_cast<int>(q[2] & 3)));
    }
  }
}

template <class Blocks>
void Boundaries::mirror_blocks(Blocks& blocks, MirrorMode mode) const {
  const bool force = mode == kMassMomentumForce;
  for (int k = 0; k < count_; ++k) {
    const Plane& pl = planes_[static_cast<std::size_t>(k)];
    if (pl.kind != BoundaryKind::symmetry && pl.kind != BoundaryKind::fixed) continue;
    const bool fixed = pl.kind == BoundaryKind::fixed;
    auto sign = [&](int d) { return fixed || d == pl.axis ? -1.0 : 1.0; };
    // (block, node) of each ghost and its partner, as mirror_impl visits them
    auto for_ghosts = [&](auto&& pass) {
      walk_ghosts(
          pl, blocks.size(), [&](std::size_t b) { return blocks.coord(b); },
          [](std::size_t) { return false; },
          [&](std::size_t, std::uint64_t key) { return blocks.find(key); },
          [&](std::size_t b, int l) {
            blocks.field(b, 1 + pl.axis)[l] = 0.0;
            if (force) blocks.field(b, 4 + pl.axis)[l] = 0.0;
          },
          [&](std::size_t b, int l) {
            for (int d = 0; d < 3; ++d) {
              blocks.field(b, 1 + d)[l] = 0.0;
              if (force) blocks.field(b, 4 + d)[l] = 0.0;
            }
          },
          pass);
    };
    for_ghosts([&](std::size_t gb, int gl, std::size_t pb, int pl_) {
      if (force) blocks.field(pb, 0)[pl_] += blocks.field(gb, 0)[gl];
      for (int d = 0; d < 3; ++d) {
        blocks.field(pb, 1 + d)[pl_] += sign(d) * blocks.field(gb, 1 + d)[gl];
        if (force) blocks.field(pb, 4 + d)[pl_] += sign(d) * blocks.field(gb, 4 + d)[gl];
      }
    });
    for_ghosts([&](std::size_t gb, int gl, std::size_t pb, int pl_) {
      if (force) blocks.field(gb, 0)[gl] = blocks.field(pb, 0)[pl_];
      for (int d = 0; d < 3; ++d) {
        blocks.field(gb, 1 + d)[gl] = sign(d) * blocks.field(pb, 1 + d)[pl_];
        if (force) blocks.field(gb, 4 + d)[gl] = sign(d) * blocks.field(pb, 4 + d)[pl_];
      }
    });
  }
}

}  // namespace shatter::mpm
