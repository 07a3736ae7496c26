// The vectorised gathers of G2P (kernels::g2p_gather) and of the velocity gradient
// (kernels::velocity_gradient_gather) against a scalar reference that reads every stencil node
// straight from the grid arrays (Stencil::node, no window) and sums in node order with one
// std::fma per component and node; and the vectorised FLIP scatter (kernels::p2g_block without
// the affine term) against a scalar scatter written with the FMAs of the scalar code. The vector
// code promises the same IEEE operations per lane (kernels/mpm/lanes.hpp), so the comparison is
// bitwise: a reordered sum, a contracted product, a misplaced window node or lane would change the
// last bits of these random sums. Each gather is also run on the stencil row the engine stores,
// read in place (kernels::StoredStencil), which must give the same bits.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <random>
#include <vector>

#include "mpm/g2p.hpp"
#include "mpm/p2g.hpp"
#include "mpm/velocity_gradient.hpp"
#include "shatter/grid/sparse_grid.hpp"

using namespace shatter;
using namespace shatter::kernels;

namespace {

bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

// A few hundred points over a few blocks on both sides of the origin, uGIMP sizes around half a
// cell, and node fields of random sign and magnitudes spread over six decades (so that the sums
// round at every node and any change of order shows).
struct Scene {
  static constexpr int kParticles = 400;
  double inv_h = 1.0 / 1.6e-3;
  std::vector<double> x, y, z, size0;
  std::vector<double> node[9];  // f*, p*, filtered velocity (x, y, z each)
  SparseGrid grid;

  template <class Shape>
  explicit Scene(Shape) {
    std::mt19937_64 rng(23);
    std::uniform_real_distribution<double> u(-0.02, 0.02), s(0.4e-3, 1.2e-3), v(-1.0, 1.0),
        e(-3.0, 3.0);
    std::vector<std::uint64_t> keys;
    for (int p = 0; p < kParticles; ++p) {
      x.push_back(u(rng));
      y.push_back(u(rng));
      z.push_back(u(rng));
      size0.push_back(s(rng));
      std::int64_t b[3];
      const double xs[3] = {x.back(), y.back(), z.back()};
      for (int d = 0; d < 3; ++d) {
        b[d] = static_cast<std::int64_t>(first_node(xs[d], inv_h, Shape::kShift)) >>
               SparseGrid::kBlockBits;
      }
      keys.push_back(SparseGrid::key(b[0], b[1], b[2]));
    }
    grid.assign(keys);
    const std::size_t n = grid.nodes().px.size();
    for (auto& f : node) {
      f.resize(n);
      for (double& a : f) a = v(rng) * std::pow(10.0, e(rng));
    }
    // The stencils as the engine's sort stage stores them, read in place by StoredStencil.
    rows.resize(x.size() * Stencil<Shape>::kRow);
    offs.resize(x.size());
    const double* const X[3] = {x.data(), y.data(), z.data()};
    store_stencils<Shape>(X, size0.data(), inv_h, 0, x.size(),
                          {rows.data(), offs.data(), StencilCache::kStore});
  }

  std::vector<double> rows;
  std::vector<std::uint8_t> offs;
  StencilCache stored() const {
    return {const_cast<double*>(rows.data()), const_cast<std::uint8_t*>(offs.data()),
            StencilCache::kLoad};
  }
};

// Particle p's stored row copied into a Stencil by hand (what Stencil::prepare does for kLoad).
// Not through prepare: it holds Stencil::compute, and one more inlined copy of compute in this
// file may round a uGIMP weight differently (-ffp-contract=fast) from the kernels' copies.
template <class Shape>
Stencil<Shape> row_stencil(const Scene& sc, std::uint32_t p) {
  constexpr int W = Shape::kWidth;
  Stencil<Shape> st{};
  const double* row = sc.rows.data() + std::size_t{p} * Stencil<Shape>::kRow;
  std::memcpy(&st.w[0][0], row, sizeof st.w);
  std::memcpy(&st.dw[0][0], row + 3 * W, sizeof st.dw);
  for (int d = 0; d < 3; ++d) st.off[d] = static_cast<int>((sc.offs[p] >> (2 * d)) & 3U);
  return st;
}

template <class Shape>
void check_g2p_gather() {
  const Scene sc{Shape{}};
  G2PWindow win;
  const double* const fields[9] = {sc.node[0].data(), sc.node[1].data(), sc.node[2].data(),
                                   sc.node[3].data(), sc.node[4].data(), sc.node[5].data(),
                                   sc.node[6].data(), sc.node[7].data(), sc.node[8].data()};
  std::size_t checked = 0;
  for (std::uint32_t b = 0; b < sc.grid.shared_blocks(); ++b) {
    if (sc.grid.owned(b).empty()) continue;
    const std::uint32_t* nb = sc.grid.neighbours(b);
    win.load(nb, fields, true);
    for (const std::uint32_t p : sc.grid.owned(b)) {
      const double x[3] = {sc.x[p], sc.y[p], sc.z[p]};
      Stencil<Shape> st;
      st.compute(x, sc.inv_h, 0.5 * sc.size0[p] * sc.inv_h, sc.grid.coord(b));
      double ref[9] = {};
      for (int a = 0; a < Shape::kWidth; ++a) {
        for (int bb = 0; bb < Shape::kWidth; ++bb) {
          const double wab = st.w[0][a] * st.w[1][bb];
          for (int c = 0; c < Shape::kWidth; ++c) {
            const double N = wab * st.w[2][c];
            const std::uint32_t g = st.node(nb, a, bb, c);
            for (int f = 0; f < 9; ++f) ref[f] = std::fma(N, sc.node[f][g], ref[f]);
          }
        }
      }
      double s[8], t[4], s_plain[8], t_plain[4] = {7.0, 7.0, 7.0, 7.0};
      g2p_gather<true>(st, win, s, t);
      g2p_gather<false>(st, win, s_plain, t_plain);
      for (int f = 0; f < 6; ++f) {
        ASSERT_TRUE(same_bits(s[f], ref[f]))
            << "particle " << p << " field " << f << ": " << s[f] << " vs " << ref[f];
        ASSERT_TRUE(same_bits(s_plain[f], ref[f])) << "particle " << p << " field " << f;
      }
      EXPECT_EQ(s[6], 0.0);  // the zero lanes stay zero
      EXPECT_EQ(s[7], 0.0);
      for (int f = 0; f < 3; ++f) {
        ASSERT_TRUE(same_bits(t[f], ref[6 + f])) << "particle " << p << " filtered " << f;
        EXPECT_EQ(t_plain[f], 7.0);  // without a filtered field the gather leaves it alone
      }
      // The stored row read in place (the engine's path) gives the bits of the same row copied
      // into a Stencil (Stencil::prepare, kLoad). Not those of `st`: the vectorised
      // store_stencils may round a uGIMP weight differently from Stencil::compute.
      const Stencil<Shape> copied = row_stencil<Shape>(sc, p);
      double s_row[8], t_row[4], s_copy[8], t_copy[4];
      g2p_gather<true>(StoredStencil<Shape>(sc.stored(), p), win, s_row, t_row);
      g2p_gather<true>(copied, win, s_copy, t_copy);
      for (int f = 0; f < 6; ++f) {
        ASSERT_TRUE(same_bits(s_row[f], s_copy[f])) << "stored row, particle " << p << " " << f;
      }
      for (int f = 0; f < 3; ++f) {
        ASSERT_TRUE(same_bits(t_row[f], t_copy[f])) << "stored row, particle " << p;
      }
      ++checked;
    }
  }
  EXPECT_EQ(checked, static_cast<std::size_t>(Scene::kParticles));
}

template <class Shape>
void check_velocity_gradient_gather() {
  const Scene sc{Shape{}};
  GradientWindow win;
  const double* fields[3] = {sc.node[3].data(), sc.node[4].data(), sc.node[5].data()};
  std::size_t checked = 0;
  for (std::uint32_t b = 0; b < sc.grid.shared_blocks(); ++b) {
    if (sc.grid.owned(b).empty()) continue;
    const std::uint32_t* nb = sc.grid.neighbours(b);
    win.load(nb, fields, 3);
    for (const std::uint32_t p : sc.grid.owned(b)) {
      const double x[3] = {sc.x[p], sc.y[p], sc.z[p]};
      Stencil<Shape> st;
      st.compute(x, sc.inv_h, 0.5 * sc.size0[p] * sc.inv_h, sc.grid.coord(b));
      double ref[3][4] = {};  // lane 3: the interpolated velocity sum N_I v_rI (r-z hoop rate)
      for (int a = 0; a < Shape::kWidth; ++a) {
        for (int bb = 0; bb < Shape::kWidth; ++bb) {
          for (int c = 0; c < Shape::kWidth; ++c) {
            const double g[4] = {
                st.dw[0][a] * st.w[1][bb] * st.w[2][c], st.w[0][a] * st.dw[1][bb] * st.w[2][c],
                st.w[0][a] * st.w[1][bb] * st.dw[2][c], st.w[0][a] * st.w[1][bb] * st.w[2][c]};
            const std::uint32_t n = st.node(nb, a, bb, c);
            for (int r = 0; r < 3; ++r) {
              for (int q = 0; q < 4; ++q) {
                ref[r][q] = std::fma(sc.node[3 + r][n], g[q], ref[r][q]);
              }
            }
          }
        }
      }
      double L[3][4], L_row[3][4], L_copy[3][4];
      velocity_gradient_gather(st, win, L);
      // The stored row in place against the same row copied (see check_g2p_gather).
      const Stencil<Shape> copied = row_stencil<Shape>(sc, p);
      velocity_gradient_gather(StoredStencil<Shape>(sc.stored(), p), win, L_row);
      velocity_gradient_gather(copied, win, L_copy);
      for (int r = 0; r < 3; ++r) {
        for (int q = 0; q < 4; ++q) {
          ASSERT_TRUE(same_bits(L[r][q], ref[r][q]))
              << "particle " << p << " L" << r << q << ": " << L[r][q] << " vs " << ref[r][q];
          ASSERT_TRUE(same_bits(L_row[r][q], L_copy[r][q]))
              << "stored row, particle " << p << " L" << r << q;
        }
      }
      ++checked;
    }
  }
  EXPECT_EQ(checked, static_cast<std::size_t>(Scene::kParticles));
}

// p2g_block (kForce: mass, momentum, internal and body force; else mass and momentum) over every
// owner block in turn, against a scalar scatter into a per-block scratch grid with
//   m += m_p N, p += m_p v_p N (one fma each) and
//   f += fma(mb, N, fma(s_z, g_z, fma(s_x, g_x, s_y g_y)))  (Eqs. 29, 30),
// flushed into the grid arrays the same way (nodes with zero scratch mass skipped). The kernel
// reads the stored stencil rows in place (kLoad, the engine's path), the reference the same rows.
template <class Shape, bool kForce>
void check_p2g_scatter() {
  Scene sc{Shape{}};
  const std::size_t n = sc.x.size();
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0), pos(0.5, 2.0), e(-3.0, 3.0);
  std::vector<double> col[14];  // vx vy vz mass rho sxx syy szz sxy syz sxz bx by bz
  for (auto& c : col) {
    c.resize(n);
    for (double& a : c) a = u(rng) * std::pow(10.0, e(rng));
  }
  for (std::size_t p = 0; p < n; ++p) {
    col[3][p] = pos(rng);        // mass
    col[4][p] = 1e3 * pos(rng);  // density
  }
  P2GParticles in{};
  in.x = sc.x.data(), in.y = sc.y.data(), in.z = sc.z.data();
  in.vx = col[0].data(), in.vy = col[1].data(), in.vz = col[2].data();
  in.mass = col[3].data(), in.rho = col[4].data(), in.size0 = sc.size0.data();
  if (kForce) {
    in.sxx = col[5].data(), in.syy = col[6].data(), in.szz = col[7].data();
    in.sxy = col[8].data(), in.syz = col[9].data(), in.sxz = col[10].data();
    in.bx = col[11].data(), in.by = col[12].data(), in.bz = col[13].data();
  }
  in.inv_h = sc.inv_h;
  in.stencil = sc.stored();  // the engine's path: the stored rows, read in place
  SparseGrid::Nodes& nodes = sc.grid.nodes();
  const std::size_t nn = nodes.px.size();
  for (auto* f : {&nodes.mass, &nodes.px, &nodes.py, &nodes.pz, &nodes.fx, &nodes.fy, &nodes.fz}) {
    f->assign(nn, 0.0);
  }
  std::vector<double> ref[7];
  for (auto& r : ref) r.assign(nn, 0.0);
  P2GScratch scratch;
  constexpr int E = P2GScratch::kEdge;
  for (std::uint32_t b = 0; b < sc.grid.shared_blocks(); ++b) {
    if (sc.grid.owned(b).empty()) continue;
    const std::uint32_t* nb = sc.grid.neighbours(b);
    p2g_block<Shape, kForce>(in, sc.grid.owned(b), sc.grid.coord(b), nb, nodes, scratch);
    std::vector<double> sr[7];
    for (auto& r : sr) r.assign(P2GScratch::kSize, 0.0);
    for (const std::uint32_t p : sc.grid.owned(b)) {
      const Stencil<Shape> st = row_stencil<Shape>(sc, p);  // the weights the kernel reads
      const double m = in.mass[p];
      const double q[4] = {m, m * in.vx[p], m * in.vy[p], m * in.vz[p]};
      double sg[6] = {}, mb[3] = {};
      if (kForce) {
        const double k = -(m / in.rho[p]) * in.inv_h;
        const double* sig[6] = {in.sxx, in.syy, in.szz, in.sxy, in.syz, in.sxz};
        for (int t = 0; t < 6; ++t) sg[t] = k * sig[t][p];
        mb[0] = m * in.bx[p], mb[1] = m * in.by[p], mb[2] = m * in.bz[p];
      }
      // rows of sigma: (xx, xy, xz), (xy, yy, yz), (xz, yz, zz)
      const double row[3][3] = {
          {sg[0], sg[3], sg[5]}, {sg[3], sg[1], sg[4]}, {sg[5], sg[4], sg[2]}};
      for (int a = 0; a < Shape::kWidth; ++a) {
        for (int bb = 0; bb < Shape::kWidth; ++bb) {
          for (int c = 0; c < Shape::kWidth; ++c) {
            const int i = ((st.off[0] + a) * E + (st.off[1] + bb)) * E + st.off[2] + c;
            const double wab = st.w[0][a] * st.w[1][bb];
            const double N = wab * st.w[2][c];
            for (int k = 0; k < 4; ++k) sr[k][i] = std::fma(q[k], N, sr[k][i]);
            if (kForce) {
              const double gx = st.dw[0][a] * st.w[1][bb] * st.w[2][c];
              const double gy = st.w[0][a] * st.dw[1][bb] * st.w[2][c];
              const double gz = wab * st.dw[2][c];
              for (int d = 0; d < 3; ++d) {
                const double syg = row[d][1] * gy;
                const double f =
                    std::fma(mb[d], N, std::fma(row[d][2], gz, std::fma(row[d][0], gx, syg)));
                sr[4 + d][i] = sr[4 + d][i] + f;
              }
            }
          }
        }
      }
    }
    WindowGeometry::visit(nb, [&](int i, std::size_t g) {
      if (sr[0][i] == 0.0) return;
      for (int k = 0; k < 7; ++k) ref[k][g] = ref[k][g] + sr[k][i];
    });
  }
  const std::vector<double>* got[7] = {&nodes.mass, &nodes.px, &nodes.py, &nodes.pz,
                                       &nodes.fx,   &nodes.fy, &nodes.fz};
  std::size_t nonzero = 0;
  for (int k = 0; k < (kForce ? 7 : 4); ++k) {
    for (std::size_t g = 0; g < nn; ++g) {
      if (k == 0 && !kForce) break;  // the momentum-only scatter leaves the mass alone
      ASSERT_TRUE(same_bits((*got[k])[g], ref[k][g]))
          << "field " << k << " node " << g << ": " << (*got[k])[g] << " vs " << ref[k][g];
      nonzero += ref[k][g] != 0.0;
    }
  }
  EXPECT_GT(nonzero, nn / 4);  // the comparison covered the scattered nodes
}

// p2g_lanes (the force scatter: mass, momentum, force) of every particle from its stored row read
// in place (StoredStencil, the engine's path) and from the same row copied into a Stencil: the
// scratch nodes must hold the same bits. Random point values, so that a misread weight shows.
template <class Shape>
void check_scatter_in_place() {
  const Scene sc{Shape{}};
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> v(-1.0, 1.0);
  auto copied_scratch = std::make_unique<P2GScratch>();
  auto row_scratch = std::make_unique<P2GScratch>();
  P2GScratch& a = *copied_scratch;
  P2GScratch& b = *row_scratch;
  for (std::uint32_t blk = 0; blk < sc.grid.shared_blocks(); ++blk) {
    if (sc.grid.owned(blk).empty()) continue;
    std::fill(a.q(0), a.q(0) + 8 * P2GScratch::kSize, 0.0);
    std::fill(b.q(0), b.q(0) + 8 * P2GScratch::kSize, 0.0);
    for (const std::uint32_t p : sc.grid.owned(blk)) {
      P2GPoint pt{v(rng), v(rng), v(rng), v(rng)};
      pt.sxx = v(rng), pt.syy = v(rng), pt.szz = v(rng);
      pt.sxy = v(rng), pt.syz = v(rng), pt.sxz = v(rng);
      pt.mbx = v(rng), pt.mby = v(rng), pt.mbz = v(rng);
      const Stencil<Shape> copied = row_stencil<Shape>(sc, p);
      p2g_lanes<true>(copied, pt, a);
      p2g_lanes<true>(StoredStencil<Shape>(sc.stored(), p), pt, b);
    }
    for (int i = 0; i < 8 * P2GScratch::kSize; ++i) {
      ASSERT_TRUE(same_bits(a.q(0)[i], b.q(0)[i])) << "block " << blk << " scratch " << i;
    }
  }
}

TEST(SimdScatter, StoredRowInPlaceMatchesTheCopiedStencil) {
  check_scatter_in_place<GimpShape>();
  check_scatter_in_place<BSpline2Shape>();
  check_scatter_in_place<LinearShape>();
}
TEST(SimdScatter, ForceScatterMatchesScalarUGimp) {
  check_p2g_scatter<GimpShape, true>();
}
TEST(SimdScatter, ForceScatterMatchesScalarLinear) {
  check_p2g_scatter<LinearShape, true>();
}
TEST(SimdScatter, MomentumScatterMatchesScalarUGimp) {
  check_p2g_scatter<GimpShape, false>();
}
TEST(SimdGather, G2PMatchesScalarUGimp) {
  check_g2p_gather<GimpShape>();
}
TEST(SimdGather, G2PMatchesScalarBSpline2) {
  check_g2p_gather<BSpline2Shape>();
}
TEST(SimdGather, G2PMatchesScalarLinear) {
  check_g2p_gather<LinearShape>();
}
TEST(SimdGather, VelocityGradientMatchesScalarUGimp) {
  check_velocity_gradient_gather<GimpShape>();
}
TEST(SimdGather, VelocityGradientMatchesScalarBSpline2) {
  check_velocity_gradient_gather<BSpline2Shape>();
}
TEST(SimdGather, VelocityGradientMatchesScalarLinear) {
  check_velocity_gradient_gather<LinearShape>();
}

}  // namespace
