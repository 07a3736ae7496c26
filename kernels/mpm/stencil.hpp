#pragma once
// The nodes a particle talks to and their weights: per-axis shape values and the position of the
// stencil inside the particle's owner block (see SparseGrid).

#include <algorithm>
#include <cstdint>

#include "mpm/shape.hpp"
#include "shatter/grid/sparse_grid.hpp"

namespace shatter::kernels {

template <class Shape>
struct Stencil {
  static constexpr int W = Shape::kWidth;
  double w[3][W];         // shape value per axis and node
  double dw[3][W];        // derivative per axis and node, in 1/cell units (multiply by 1/h)
  int off[3];             // first stencil node relative to the owner block's first node (0..3)
  std::int64_t first[3];  // first stencil node, global index per axis

  // First node of the stencil (global node index per axis) for a particle at xi (cell units).
  static std::int64_t first_node(double xi) {
    double w_[W], dw_[W];
    return Shape::weights(xi, 0.25, w_, dw_);
  }

  // half_size: uGIMP particle half-width in cell units, clamped to 1/2 so that the support stays
  // within three nodes.
  void compute(const double xi[3], double half_size, const SparseGrid::Coord& owner) {
    const double lp = std::min(half_size, 0.5);
    const int base[3] = {owner.x * SparseGrid::kBlock, owner.y * SparseGrid::kBlock,
                         owner.z * SparseGrid::kBlock};
    for (int d = 0; d < 3; ++d) {
      first[d] = Shape::weights(xi[d], lp, w[d], dw[d]);
      off[d] = static_cast<int>(first[d] - base[d]);
    }
  }

  // Node minus particle position along axis d for stencil node a, in metres (APIC's x_i - x_p).
  double offset(int d, int a, double xi_d, double h) const {
    return (static_cast<double>(first[d] + a) - xi_d) * h;
  }

  // Global node index of stencil node (a, b, c).
  std::uint32_t node(const std::uint32_t* neighbours, int a, int b, int c) const {
    const int lx = off[0] + a, ly = off[1] + b, lz = off[2] + c;
    const int s = (lx >> SparseGrid::kBlockBits) | ((ly >> SparseGrid::kBlockBits) << 1) |
                  ((lz >> SparseGrid::kBlockBits) << 2);
    constexpr int m = SparseGrid::kBlock - 1;
    return neighbours[s] * SparseGrid::kBlockNodes + SparseGrid::local(lx & m, ly & m, lz & m);
  }
};

}  // namespace shatter::kernels
