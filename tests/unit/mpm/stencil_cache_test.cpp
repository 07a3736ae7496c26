// The stencils the sort stage stores once per step (kernels::store_stencils) against the ones
// each transfer computed for itself before (Stencil::compute), and the block-local node window
// of the gathers (kernels::NodeWindow) against the direct per-node lookup (Stencil::node).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <random>
#include <vector>

#include "mpm/p2g.hpp"
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
    return static_cast<std::int64_t>(first_node(v, inv_h, GimpShape::kShift)) >>
           SparseGrid::kBlockBits;
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
    const double x[3] = {c.x[p], c.y[p], c.z[p]};
    // The owner block as the sort stage derives it (kernels::first_node / 4).
    std::int32_t ob[3];
    for (int d = 0; d < 3; ++d) {
      ob[d] = static_cast<std::int32_t>(
          static_cast<std::int64_t>(first_node(x[d], c.inv_h, Shape::kShift)) >> 2);
    }
    const SparseGrid::Coord owner{ob[0], ob[1], ob[2]};
    Stencil<Shape> fresh, cached;
    fresh.compute(x, c.inv_h, 0.5 * c.size0[p] * c.inv_h, owner);
    cached.prepare(load, p, x, c.inv_h, 0.0, owner);
    for (int d = 0; d < 3; ++d) {
      // Node indices exactly; weights to round-off: the first node and the remainder are
      // fused explicitly (kernels::first_node), but the two inlined copies of a shape's own
      // polynomial may still be contracted differently (the B-spline's 3/4 - b^2), by a few
      // ulps; 1e-13 bounds that with margin.
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
// cell and points at negative coordinates. Bitwise in every build: the fusions are explicit
// (std::fma) in GimpShape and gimp_rows alike, and no other product meets a sum.

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
  const auto same = [](double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; };
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
          const double x[3] = {0, 0, 0};
          one.prepare(re, p, x, c.inv_h, 0.0, owner);
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

// The first stencil node of a particle is taken in one place (kernels::first_node): the sort's
// owner key (src/mpm/stages/sort.cpp calls it), the stored rows, the recomputed uGIMP rows (one at
// a time and eight per vector), Stencil::compute and the multi-field mass gradient (which reads the
// step's rows) must all find the node the key found, or a row lands in the wrong block. The
// positions are those where x / h - shift is a whole number up to round-off: lattices of 1, 2
// and 3 points per cell (1 per cell: the cell centres, where an unfused and a fused x / h - 1/2
// part), cell faces, over several cell sizes and origins, and random ones.
std::vector<double> awkward_coordinates(double h, std::mt19937_64& rng) {
  std::vector<double> v;
  for (int ppc = 1; ppc <= 3; ++ppc) {
    const double dx = h / ppc;
    for (const double lo : {0.0, -10.0 * h, 3.0 * h, -0.37, 0.021}) {
      for (int k = -40; k < 40; ++k) {
        v.push_back(lo + (k + 0.5) * dx);
        v.push_back(lo + 0.5 * dx + k * dx);
      }
    }
  }
  for (int k = -40; k < 40; ++k) {
    v.push_back(k * h);
    v.push_back((k + 0.5) * h);
    v.push_back(k * h + 0.5 * h);
  }
  std::uniform_real_distribution<double> u(-50.0 * h, 50.0 * h);
  for (int k = 0; k < 400; ++k) v.push_back(u(rng));
  return v;
}

template <class Shape>
void check_first_nodes_agree(double h) {
  std::mt19937_64 rng(29);
  const std::vector<double> xs = awkward_coordinates(h, rng);
  const std::size_t n = xs.size();
  std::vector<double> x(xs), y(n), z(n), size0(n), mass(n, 1.0);
  for (std::size_t p = 0; p < n; ++p) {
    y[p] = xs[(p + n / 3) % n];
    z[p] = xs[(p + 2 * n / 3) % n];
    size0[p] = h / static_cast<double>(1 + p % 3);  // 1, 2, 3 points per cell
  }
  const double inv_h = 1.0 / h;
  const double* X[3] = {x.data(), y.data(), z.data()};
  std::vector<std::int64_t> key[3];  // the owner key's first node (sort.cpp)
  for (int d = 0; d < 3; ++d) {
    for (std::size_t p = 0; p < n; ++p) {
      key[d].push_back(static_cast<std::int64_t>(first_node(X[d][p], inv_h, Shape::kShift)));
    }
  }
  const auto owner = [&](std::size_t p) {
    return SparseGrid::Coord{static_cast<std::int32_t>(key[0][p] >> SparseGrid::kBlockBits),
                             static_cast<std::int32_t>(key[1][p] >> SparseGrid::kBlockBits),
                             static_cast<std::int32_t>(key[2][p] >> SparseGrid::kBlockBits)};
  };
  const auto key_off = [&](std::size_t p, int d) { return static_cast<int>(key[d][p] & 3); };
  // The stored rows (the sort stage's store_stencils).
  std::vector<double> w(n * Stencil<Shape>::kRow);
  std::vector<std::uint8_t> off(n);
  store_stencils<Shape>(X, size0.data(), inv_h, 0, n, {w.data(), off.data(), StencilCache::kStore});
  // What the transfers read: the stored rows, or the recomputed uGIMP rows.
  StencilCache rows{w.data(), off.data(), StencilCache::kLoad};
  if constexpr (kRecomputedRows<Shape>) {
    rows = StencilCache{};
    rows.mode = StencilCache::kRecompute;
    for (int d = 0; d < 3; ++d) rows.x[d] = X[d];
    rows.size0 = size0.data();
    rows.inv_h = inv_h;
  }
  std::size_t mismatches = 0;
  for (std::size_t p = 0; p < n; ++p) {
    const double xp[3] = {x[p], y[p], z[p]};
    Stencil<Shape> fresh, read;
    fresh.compute(xp, inv_h, 0.5 * size0[p] * inv_h, owner(p));
    read.prepare(rows, p, xp, inv_h, 0.5 * size0[p] * inv_h, owner(p));
    for (int d = 0; d < 3; ++d) {
      mismatches += ((off[p] >> (2 * d)) & 3) != key_off(p, d);
      mismatches += fresh.first[d] != key[d][p];
      mismatches += read.first[d] != key[d][p];
    }
  }
  if constexpr (kRecomputedRows<Shape>) {  // the batch (AVX-512: eight particles per vector)
    std::vector<std::uint32_t> all(n);
    for (std::size_t p = 0; p < n; ++p) all[p] = static_cast<std::uint32_t>(p);
    for_each_recomputed<Shape>(rows, all, [&](const BatchStencil<Shape>& st, std::uint32_t p) {
      for (int d = 0; d < 3; ++d) mismatches += st.off[d] != key_off(p, d);
    });
  }
  EXPECT_EQ(mismatches, 0U) << "h = " << h;
  // The mass gradient scatters particle p alone into the scratch window of its owner block (no
  // node is a body copy, so nothing leaves the window). Its sums of N_I place the particle where
  // it is (sum_I N_I x_I = x_p, window units): a first node off by one across a block face moves
  // it by a whole block where the offset wraps (2 bits, as the rows pack it). Where it does not
  // wrap (Stencil::compute's offset 4 or -1), the node beyond the window has weight 0, and only
  // the write tells: the arrays after the window (px, ..., which the mass gradient leaves alone)
  // hold -0, which adding a +0 turns into +0.
  P2GParticles in{};
  in.x = x.data(), in.y = y.data(), in.z = z.data(), in.mass = mass.data();
  in.size0 = size0.data(), in.inv_h = inv_h, in.stencil = rows;
  const auto scratch = std::make_unique<P2GScratch>();
  SparseGrid::Nodes nodes;
  const std::uint32_t nb[8] = {0, 1, 2, 3, 4, 5, 6, 7};
  constexpr int E = P2GScratch::kEdge;
  std::size_t misplaced = 0;
  for (std::size_t p = 0; p < n; ++p) {
    const std::uint32_t one[1] = {static_cast<std::uint32_t>(p)};
    for (double* a : {scratch->px, scratch->py, scratch->pz}) std::fill(a, a + E * E * E, -0.0);
    mass_gradient_block<Shape>(in, one, owner(p), nb, 8, nodes, *scratch);
    for (const double* a : {scratch->px, scratch->py, scratch->pz}) {
      misplaced += std::count_if(a, a + E * E * E, [](double v) { return !std::signbit(v); });
    }
    double sum = 0.0, at[3] = {0.0, 0.0, 0.0};
    for (int i = 0; i < P2GScratch::kSize; ++i) {
      const double m = scratch->m[i];
      const int l[3] = {i / (E * E), (i / E) % E, i % E};
      sum += m;
      for (int d = 0; d < 3; ++d) at[d] += m * l[d];
    }
    for (int d = 0; d < 3; ++d) {
      const double expect = key_off(p, d) + (X[d][p] * inv_h - static_cast<double>(key[d][p]));
      misplaced += !(std::abs(at[d] / sum - expect) < 1e-6);
    }
  }
  EXPECT_EQ(misplaced, 0U) << "h = " << h;
}

TEST(StencilCache, EveryPathTakesTheKeysFirstNode) {
  for (const double h : {1.6e-3, 1e-3, 0.1, 0.05, 2.5e-4, 1.0 / 3.0, 7e-3}) {
    check_first_nodes_agree<GimpShape>(h);
    check_first_nodes_agree<BSpline2Shape>(h);
    check_first_nodes_agree<LinearShape>(h);
  }
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
      const double x[3] = {c.x[p], c.y[p], c.z[p]};
      Stencil<Shape> st;
      st.compute(x, c.inv_h, 0.5 * c.size0[p] * c.inv_h, grid.coord(b));
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
