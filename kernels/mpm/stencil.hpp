#pragma once
// The nodes a particle talks to and their weights: per-axis shape values and the position of the
// stencil inside the particle's owner block (see SparseGrid).

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "mpm/shape.hpp"
#include "shatter/grid/sparse_grid.hpp"

namespace shatter::kernels {

// The stencils of one step, computed once and reused. The particles do not move between the
// P2G of step 1 and the velocity gradient of step 7 (positions advance only at the end of the
// step), so the shape functions at x^n that steps 1, 5, 6 and 7 of App. A.2 evaluate are the
// same four times. store_stencils (below; the engine's sort stage) stores them once and P2G,
// G2P, the MUSL remap and the velocity gradient read them back (kLoad); kCompute remains for
// callers without a cache. The four passes now use one set of weights per particle; before,
// each evaluated them in its own inlined code, where the compiler's FMA contraction of
// x / h - floor could differ in the last bits (docs/performance.md).
struct StencilCache {
  enum Mode : std::uint8_t { kCompute, kStore, kLoad };
  double* w = nullptr;          // per particle: w[3][W] then dw[3][W] (6 W doubles)
  std::uint8_t* off = nullptr;  // per particle: off[0] | off[1] << 2 | off[2] << 4
  Mode mode = kCompute;
};

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

  static constexpr int kRow = 6 * W;  // doubles per particle in a StencilCache

  // The stencil of particle p: computed, computed and stored, or loaded (StencilCache::Mode).
  void prepare(const StencilCache& cache, std::size_t p, const double xi[3], double half_size,
               const SparseGrid::Coord& owner) {
    if (cache.mode == StencilCache::kLoad) {
      const double* row = cache.w + p * kRow;
      std::copy(row, row + 3 * W, &w[0][0]);
      std::copy(row + 3 * W, row + kRow, &dw[0][0]);
      const unsigned o = cache.off[p];
      const int base[3] = {owner.x * SparseGrid::kBlock, owner.y * SparseGrid::kBlock,
                           owner.z * SparseGrid::kBlock};
      for (int d = 0; d < 3; ++d) {
        off[d] = static_cast<int>((o >> (2 * d)) & 3U);
        first[d] = base[d] + off[d];
      }
      return;
    }
    compute(xi, half_size, owner);
    if (cache.mode == StencilCache::kStore) {
      double* row = cache.w + p * kRow;
      std::copy(&w[0][0], &w[0][0] + 3 * W, row);
      std::copy(&dw[0][0], &dw[0][0] + 3 * W, row + 3 * W);
      cache.off[p] = static_cast<std::uint8_t>(off[0] | (off[1] << 2) | (off[2] << 4));
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

// A stored stencil read in place (StencilCache::kLoad): particle p's weights and derivatives
// straight from its cache row, with no copy into a Stencil. Stencil::prepare copies the row with
// vector stores, and the gathers' scalar loads of single weights right after cannot be forwarded
// from a wider store (the likely cause): they wait for the store to retire. Read in place, the
// velocity gradient's arithmetic core (bench/transfer_lanes.cpp) takes 25 instead of 49 ns per
// particle, G2P's 20 instead of 25 (docs/performance.md, "MPM transfers, round 4"). Same values,
// same operations: the same bits.
template <class Shape>
struct StoredStencil {
  static constexpr int W = Shape::kWidth;
  const double (*w)[W];   // w[3][W] of the row
  const double (*dw)[W];  // dw[3][W] of the row
  int off[3];             // as Stencil::off

  StoredStencil(const StencilCache& cache, std::size_t p)
      : w(reinterpret_cast<const double (*)[W]>(cache.w + p * Stencil<Shape>::kRow)),
        dw(reinterpret_cast<const double (*)[W]>(cache.w + p * Stencil<Shape>::kRow + 3 * W)) {
    const unsigned o = cache.off[p];
    for (int d = 0; d < 3; ++d) off[d] = static_cast<int>((o >> (2 * d)) & 3U);
  }
};

// Global node index of stencil node (a, b, c) of a Stencil or a StoredStencil (Stencil::node).
template <class St>
std::uint32_t node_index(const St& st, const std::uint32_t* neighbours, int a, int b, int c) {
  const int lx = st.off[0] + a, ly = st.off[1] + b, lz = st.off[2] + c;
  const int s = (lx >> SparseGrid::kBlockBits) | ((ly >> SparseGrid::kBlockBits) << 1) |
                ((lz >> SparseGrid::kBlockBits) << 2);
  constexpr int m = SparseGrid::kBlock - 1;
  return neighbours[s] * SparseGrid::kBlockNodes + SparseGrid::local(lx & m, ly & m, lz & m);
}

// The degenerate axis of the axisymmetric mode: node 0 with weight 1, derivative 0.
template <int W>
int degenerate_weights(double (&w)[W], double (&dw)[W]) {
  for (int a = 0; a < W; ++a) w[a] = dw[a] = 0.0;
  w[0] = 1.0;
  return 0;
}

// Stores the stencils of particles [begin, end) in `cache` (StencilCache layout), straight from
// the positions: the offset of the first node inside its owner block is its global index modulo
// kBlock, since the owner block is the block of the first node (SparseGrid). One streaming pass
// over the particles, vectorisable, instead of four evaluations inside the transfer loops.
//
// kAxisymmetric (SolverConfig::Geometry): the y axis is degenerate, every point at y = 0 and its
// y stencil the single node y = 0 with weight 1 and derivative 0 (the other W - 1 entries of
// weight 0 add nothing). The grid is then one layer of nodes in (x, z) = (r, z), and every
// transfer that reads the cache (P2G, G2P, remap, filters, velocity gradient) works in r-z.
template <class Shape, bool kAxisymmetric = false>
void store_stencils(const double* const (&x)[3], const double* size0, double inv_h,
                    std::size_t begin, std::size_t end, const StencilCache& cache) {
  constexpr int W = Shape::kWidth;
  constexpr int mask = SparseGrid::kBlock - 1;
  for (std::size_t p = begin; p < end; ++p) {
    const double lp = std::min(0.5 * size0[p] * inv_h, 0.5);
    double* row = cache.w + p * Stencil<Shape>::kRow;
    unsigned packed = 0;
    for (int d = 0; d < 3; ++d) {
      double w[W], dw[W];
      const int first = kAxisymmetric && d == 1 ? degenerate_weights<W>(w, dw)
                                                : Shape::weights(x[d][p] * inv_h, lp, w, dw);
      for (int a = 0; a < W; ++a) {
        row[d * W + a] = w[a];
        row[(3 + d) * W + a] = dw[a];
      }
      packed |= static_cast<unsigned>(first & mask) << (2 * d);
    }
    cache.off[p] = static_cast<std::uint8_t>(packed);
  }
}

// The nodes of the 2x2x2 blocks that the stencils of one owner block reach, copied into one
// padded cube of (kBlock + 2)^3 nodes (the reverse of P2GScratch's flush in p2g.hpp). A gather
// (G2P, velocity gradient) then finds stencil node (a, b, c) at a fixed stride, with no block
// lookup per node. WindowGeometry is the cube; NodeWindow holds F fields one after the other,
// G2PWindow (g2p.hpp) the fields of each node side by side.
struct WindowGeometry {
  static constexpr int kEdge = SparseGrid::kBlock + 2;
  static constexpr int kSize = kEdge * kEdge * kEdge;

  // body(i, g) for every window node i and its grid node g, through the owner's neighbour list
  // (8 blocks).
  template <class Body>
  static void visit(const std::uint32_t* neighbours, Body&& body) {
    constexpr int mask = SparseGrid::kBlock - 1;
    constexpr int bits = SparseGrid::kBlockBits;
    for (int lx = 0; lx < kEdge; ++lx) {
      for (int ly = 0; ly < kEdge; ++ly) {
        const int sel_xy = (lx >> bits) | ((ly >> bits) << 1);
        for (int lz = 0; lz < kEdge; ++lz) {
          const int i = (lx * kEdge + ly) * kEdge + lz;
          const std::size_t g =
              std::size_t{neighbours[sel_xy | ((lz >> bits) << 2)]} * SparseGrid::kBlockNodes +
              static_cast<std::size_t>(SparseGrid::local(lx & mask, ly & mask, lz & mask));
          body(i, g);
        }
      }
    }
  }

  // Window index of stencil node (a, b, 0); node (a, b, c) is at row(st, a, b) + c. St: a
  // Stencil or a StoredStencil.
  template <class St>
  static int row(const St& st, int a, int b) {
    return ((st.off[0] + a) * kEdge + (st.off[1] + b)) * kEdge + st.off[2];
  }
};

// F node fields, one array each.
template <int F>
struct NodeWindow : WindowGeometry {
  double v[F][kSize];

  // Copies `count` (<= F) node fields.
  void load(const std::uint32_t* neighbours, const double* const* fields, int count) {
    visit(neighbours, [&](int i, std::size_t g) {
      for (int f = 0; f < count; ++f) v[f][i] = fields[f][g];
    });
  }
};

}  // namespace shatter::kernels
