// The vectorised gathers of G2P (kernels::g2p_gather) and of the velocity gradient
// (kernels::velocity_gradient_gather) against a scalar reference that reads every stencil node
// straight from the grid arrays (Stencil::node, no window) and sums in node order with one
// std::fma per component and node. The vector code promises the same IEEE operations per lane
// (kernels/mpm/lanes.hpp), so the comparison is bitwise: a reordered sum, a contracted product, a
// misplaced window node or lane would change the last bits of these random sums.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include "mpm/g2p.hpp"
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
        b[d] = Stencil<Shape>::first_node(xs[d] * inv_h) >> SparseGrid::kBlockBits;
      }
      keys.push_back(SparseGrid::key(b[0], b[1], b[2]));
    }
    grid.assign(keys);
    const std::size_t n = grid.nodes().px.size();
    for (auto& f : node) {
      f.resize(n);
      for (double& a : f) a = v(rng) * std::pow(10.0, e(rng));
    }
  }
};

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
      const double xi[3] = {sc.x[p] * sc.inv_h, sc.y[p] * sc.inv_h, sc.z[p] * sc.inv_h};
      Stencil<Shape> st;
      st.compute(xi, 0.5 * sc.size0[p] * sc.inv_h, sc.grid.coord(b));
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
      const double xi[3] = {sc.x[p] * sc.inv_h, sc.y[p] * sc.inv_h, sc.z[p] * sc.inv_h};
      Stencil<Shape> st;
      st.compute(xi, 0.5 * sc.size0[p] * sc.inv_h, sc.grid.coord(b));
      double ref[3][3] = {};
      for (int a = 0; a < Shape::kWidth; ++a) {
        for (int bb = 0; bb < Shape::kWidth; ++bb) {
          for (int c = 0; c < Shape::kWidth; ++c) {
            const double g[3] = {st.dw[0][a] * st.w[1][bb] * st.w[2][c],
                                 st.w[0][a] * st.dw[1][bb] * st.w[2][c],
                                 st.w[0][a] * st.w[1][bb] * st.dw[2][c]};
            const std::uint32_t n = st.node(nb, a, bb, c);
            for (int r = 0; r < 3; ++r) {
              for (int q = 0; q < 3; ++q) {
                ref[r][q] = std::fma(sc.node[3 + r][n], g[q], ref[r][q]);
              }
            }
          }
        }
      }
      double L[3][4];
      velocity_gradient_gather(st, win, L);
      for (int r = 0; r < 3; ++r) {
        for (int q = 0; q < 3; ++q) {
          ASSERT_TRUE(same_bits(L[r][q], ref[r][q]))
              << "particle " << p << " L" << r << q << ": " << L[r][q] << " vs " << ref[r][q];
        }
        EXPECT_EQ(L[r][3], 0.0);
      }
      ++checked;
    }
  }
  EXPECT_EQ(checked, static_cast<std::size_t>(Scene::kParticles));
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
