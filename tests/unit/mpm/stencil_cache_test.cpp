// The stencils the sort stage stores once per step (kernels::store_stencils) against the ones
// each transfer computed for itself before (Stencil::compute), and the block-local node window
// of the gathers (kernels::NodeWindow) against the direct per-node lookup (Stencil::node).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include "mpm/stencil.hpp"
#include "shatter/grid/sparse_grid.hpp"

using namespace shatter;
using namespace shatter::kernels;

namespace {

// Points scattered over a few blocks on both sides of the origin (negative block coordinates
// exercise the offset arithmetic), with uGIMP sizes around half a cell.
struct Cloud {
  std::vector<double> x, y, z, size0;
  double inv_h = 1.0 / 1.6e-3;
  explicit Cloud(int n) {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-0.03, 0.03), s(0.4e-3, 1.2e-3);
    for (int p = 0; p < n; ++p) {
      x.push_back(u(rng));
      y.push_back(u(rng));
      z.push_back(u(rng));
      size0.push_back(s(rng));
    }
  }
  std::int64_t owner_axis(double v) const {
    return static_cast<std::int64_t>(std::floor(v * inv_h - 0.5)) >> SparseGrid::kBlockBits;
  }
};

template <class Shape>
void check_cache_matches_compute() {
  const Cloud c(4000);
  const std::size_t n = c.x.size();
  std::vector<double> w(n * Stencil<Shape>::kRow);
  std::vector<std::uint8_t> off(n);
  const double* X[3] = {c.x.data(), c.y.data(), c.z.data()};
  store_stencils<Shape>(X, c.size0.data(), c.inv_h, 0, n,
                        {w.data(), off.data(), StencilCache::kStore});
  const StencilCache load{w.data(), off.data(), StencilCache::kLoad};
  for (std::size_t p = 0; p < n; ++p) {
    const double xi[3] = {c.x[p] * c.inv_h, c.y[p] * c.inv_h, c.z[p] * c.inv_h};
    // The owner block as the sort stage derives it for 3-wide stencils (floor(xi - 1/2) / 4);
    // for the 2-wide linear stencil it is floor(xi) / 4.
    const double shift = Shape::kWidth == 3 ? 0.5 : 0.0;
    const SparseGrid::Coord owner{
        static_cast<std::int32_t>(static_cast<std::int64_t>(std::floor(xi[0] - shift)) >> 2),
        static_cast<std::int32_t>(static_cast<std::int64_t>(std::floor(xi[1] - shift)) >> 2),
        static_cast<std::int32_t>(static_cast<std::int64_t>(std::floor(xi[2] - shift)) >> 2)};
    Stencil<Shape> fresh, cached;
    fresh.compute(xi, 0.5 * c.size0[p] * c.inv_h, owner);
    cached.prepare(load, p, xi, 0.0, owner);
    for (int d = 0; d < 3; ++d) {
      // Node indices exactly; weights to round-off: the two evaluations may differ only in
      // where the compiler contracts xi = x / h into the floor's remainder (an FMA), i.e. by a
      // few ulps of xi (~1e-16 x |xi| <= ~20 cells here); 1e-13 bounds that with margin.
      ASSERT_EQ(cached.first[d], fresh.first[d]) << "particle " << p << " axis " << d;
      ASSERT_EQ(cached.off[d], fresh.off[d]);
      ASSERT_GE(cached.off[d], 0);
      ASSERT_LT(cached.off[d], SparseGrid::kBlock);
      for (int a = 0; a < Shape::kWidth; ++a) {
        EXPECT_NEAR(cached.w[d][a], fresh.w[d][a], 1e-13);
        EXPECT_NEAR(cached.dw[d][a], fresh.dw[d][a], 1e-13);
      }
    }
  }
}

TEST(StencilCache, StoredStencilsMatchComputedUGimp) {
  check_cache_matches_compute<GimpShape>();
}
TEST(StencilCache, StoredStencilsMatchComputedBSpline2) {
  check_cache_matches_compute<BSpline2Shape>();
}
TEST(StencilCache, StoredStencilsMatchComputedLinear) {
  check_cache_matches_compute<LinearShape>();
}

// uGIMP rows are recomputed at every read (StencilCache::kRecompute) instead of stored: the
// batch (recomputed_rows, eight particles per vector with AVX-512), the single-particle form
// (Stencil::prepare) and the stored rows of store_stencils must hold the same bits, on 3-D and
// r-z rows. The cloud adds the cases where a piece of GimpShape::node changes: distances of
// exactly lp, 1 - lp and 1 + lp, particles on a node (d = +-0), x = -0, sizes clamped to half a
// cell and points at negative coordinates. Bitwise where the build contracts into FMAs as the
// engine's Release build (store_stencils' x / h then has fused remainders); otherwise, where the
// old rows were unfused, within round-off.

// Whether this file is compiled with contraction into FMAs, as the engine's store_stencils is in
// the Release build (GCC at -O2 and above where the CPU has FMA; not at -O1, the sanitizer tree):
// (1 + 2^-30)(1 - 2^-30) - 1 is 0 with the product rounded, -2^-60 fused.
bool contracts() {
  volatile double va = 1.0 + 0x1p-30, vb = 1.0 - 0x1p-30, vc = -1.0;
  const double a = va, b = vb, c = vc;
  return a * b + c != 0.0;
}

void check_recomputed_rows(bool axisymmetric) {
  Cloud c(1 << 15);
  const double h = 1.0 / c.inv_h;
  for (int k = 0; k < 2000; ++k) {  // piece boundaries, with lp = 0.25 and lp = 0.5
    const double size = k % 2 == 0 ? 0.5 * h : 1.3 * h;
    const double lp = std::min(0.5 * size * c.inv_h, 0.5);
    const double at[] = {0.0, lp, 1.0 - lp, 1.0 + lp, -lp, 0.5};
    const double node = static_cast<double>(k % 23 - 11);
    c.x.push_back((node + at[k % 6]) * h);
    c.y.push_back((node + at[(k / 6) % 6] + 0.5) * h);
    c.z.push_back(k % 7 == 0 ? -0.0 : (node - at[(k / 36) % 6]) * h);
    c.size0.push_back(size);
  }
  const std::size_t n = c.x.size();
  std::vector<double> w(n * Stencil<GimpShape>::kRow);
  std::vector<std::uint8_t> off(n);
  const double* X[3] = {c.x.data(), c.y.data(), c.z.data()};
  const StencilCache store{w.data(), off.data(), StencilCache::kStore};
  if (axisymmetric) {
    store_stencils<GimpShape, true>(X, c.size0.data(), c.inv_h, 0, n, store);
  } else {
    store_stencils<GimpShape>(X, c.size0.data(), c.inv_h, 0, n, store);
  }
  StencilCache re;
  re.mode = StencilCache::kRecompute;
  for (int d = 0; d < 3; ++d) re.x[d] = X[d];
  re.size0 = c.size0.data();
  re.inv_h = c.inv_h;
  re.axisymmetric = axisymmetric;
  // Runs of consecutive particles (the engine's usual case, read with vector loads), of
  // particles in reverse, and of consecutive ones with two swapped (first and last in place).
  std::vector<std::uint32_t> all(n);
  for (std::size_t p = 0; p < n; ++p) {
    all[p] = static_cast<std::uint32_t>(p < n / 2 ? p : n - 1 - (p - n / 2));
  }
  for (std::size_t p = n / 4; p + 8 < n / 2; p += 16) std::swap(all[p + 2], all[p + 3]);
  std::size_t visited = 0, differ = 0;
  const bool bitwise = contracts();
  const auto same = [&](double a, double b) {
    return bitwise ? std::memcmp(&a, &b, sizeof a) == 0 : std::abs(a - b) <= 1e-13;
  };
  constexpr int W = GimpShape::kWidth;
  // Runs of 1..11 particles, so that every tail length of the batch is taken.
  for (std::size_t k0 = 0; k0 < n;) {
    const std::size_t len = std::min<std::size_t>(1 + k0 % 11, n - k0);
    for_each_recomputed<GimpShape>(
        re, std::span<const std::uint32_t>(all).subspan(k0, len),
        [&](const BatchStencil<GimpShape>& st, std::uint32_t p) {
          ++visited;
          const double* row = &w[p * Stencil<GimpShape>::kRow];
          const SparseGrid::Coord owner{0, 0, 0};
          Stencil<GimpShape> one;
          const double xi[3] = {0, 0, 0};
          one.prepare(re, p, xi, 0.0, owner);
          for (int d = 0; d < 3; ++d) {
            ASSERT_EQ(st.off[d], (off[p] >> (2 * d)) & 3) << "particle " << p << " axis " << d;
            ASSERT_EQ(one.off[d], st.off[d]);
            for (int a = 0; a < W; ++a) {
              differ +=
                  !same(st.w[d][a], row[d * W + a]) + !same(st.dw[d][a], row[(3 + d) * W + a]);
              differ +=
                  !same(one.w[d][a], row[d * W + a]) + !same(one.dw[d][a], row[(3 + d) * W + a]);
            }
          }
        });
    k0 += len;
  }
  EXPECT_EQ(visited, n);
  EXPECT_EQ(differ, 0U);
}

TEST(StencilCache, RecomputedUGimpRowsAreTheStoredBits) {
  check_recomputed_rows(false);
}
TEST(StencilCache, RecomputedUGimpRowsAreTheStoredBitsRz) {
  check_recomputed_rows(true);
}

// Every stencil node read through the window holds the same value as the node the direct lookup
// finds in the grid arrays (exact: a copy). Node values are distinct (their global index), so
// a misplaced node cannot pass.
TEST(StencilCache, NodeWindowHoldsTheStencilNodes) {
  using Shape = GimpShape;
  const Cloud c(3000);
  std::vector<std::uint64_t> keys;
  for (std::size_t p = 0; p < c.x.size(); ++p) {
    keys.push_back(
        SparseGrid::key(c.owner_axis(c.x[p]), c.owner_axis(c.y[p]), c.owner_axis(c.z[p])));
  }
  SparseGrid grid;
  grid.assign(keys);
  auto& N = grid.nodes();
  for (std::size_t i = 0; i < N.px.size(); ++i) {
    N.px[i] = static_cast<double>(i);
    N.py[i] = -static_cast<double>(i);
    N.pz[i] = 0.5 * static_cast<double>(i);
  }
  const double* fields[3] = {N.px.data(), N.py.data(), N.pz.data()};
  NodeWindow<3> win;
  std::size_t checked = 0;
  for (std::uint32_t b = 0; b < grid.shared_blocks(); ++b) {
    if (grid.owned(b).empty()) continue;
    win.load(grid.neighbours(b), fields, 3);
    for (const std::uint32_t p : grid.owned(b)) {
      const double xi[3] = {c.x[p] * c.inv_h, c.y[p] * c.inv_h, c.z[p] * c.inv_h};
      Stencil<Shape> st;
      st.compute(xi, 0.5 * c.size0[p] * c.inv_h, grid.coord(b));
      for (int a = 0; a < Shape::kWidth; ++a) {
        for (int bb = 0; bb < Shape::kWidth; ++bb) {
          for (int cc = 0; cc < Shape::kWidth; ++cc) {
            const std::uint32_t g = st.node(grid.neighbours(b), a, bb, cc);
            const int i = NodeWindow<3>::row(st, a, bb) + cc;
            ASSERT_EQ(win.v[0][i], N.px[g]);
            ASSERT_EQ(win.v[1][i], N.py[g]);
            ASSERT_EQ(win.v[2][i], N.pz[g]);
            ++checked;
          }
        }
      }
    }
  }
  EXPECT_EQ(checked, 27 * c.x.size());
}

}  // namespace
