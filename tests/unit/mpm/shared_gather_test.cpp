// The gathers with the particles that share a stencil in the lanes of one vector
// (kernels/mpm/shared.hpp) against the one-particle gathers they replace, on the engine's
// recomputed uGIMP rows: g2p_block and velocity_gradient_block with StencilCache::shared_lanes
// must write the bits they write without it, for every particle (in 3-D and r-z). The particles
// sit two per cell and axis (the engine's lattice), moved by up to a quarter of the spacing,
// plus a few scattered ones, so that runs of every length from 1 to 8 occur (and longer ones,
// cut at 8); the lists are in the engine's canonical order (body, id), ids not in store order.
#include <gtest/gtest.h>

#include <algorithm>
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

struct Cloud {
  double inv_h = 1.0 / 2.4e-3;
  std::vector<double> x[3], size0;
  std::vector<std::int64_t> ids;
  std::vector<std::uint8_t> bases;  // stencil bases, for the test of the runs
  std::vector<double> node[9];      // f*, p*, filtered velocity
  SparseGrid grid;

  bool rz = false;  // axisymmetric: y = 0 and the degenerate y stencil

  explicit Cloud(bool axisymmetric = false) : rz(axisymmetric) {
    std::mt19937_64 rng(35);
    std::uniform_real_distribution<double> jitter(-0.25, 0.25), u(-6.0, 6.0), v(-1.0, 1.0),
        e(-3.0, 3.0);
    const double h = 1.0 / inv_h;
    for (int i = -6; i < 6; ++i) {
      for (int j = -4; j < 4; ++j) {
        for (int k = -4; k < 4; ++k) {
          const int q[3] = {i, j, k};
          for (int d = 0; d < 3; ++d) x[d].push_back((0.5 * q[d] + 0.75 + jitter(rng) * 0.5) * h);
          if (rz) x[1].back() = 0.0, x[0].back() = std::abs(x[0].back()) + 0.1 * h;
        }
      }
    }
    for (int p = 0; p < 40; ++p) {
      for (auto& c : x) c.push_back(u(rng) * h);
      if (rz) x[1].back() = 0.0, x[0].back() = std::abs(x[0].back()) + 0.1 * h;
    }
    const std::size_t n = x[0].size();
    std::vector<std::uint64_t> keys(n);
    for (std::size_t p = 0; p < n; ++p) {
      size0.push_back(0.5 * h * (1.0 + 0.1 * v(rng)));
      ids.push_back(static_cast<std::int64_t>((p * 7919) % n));  // ids not in store order
      std::int64_t b[3];
      unsigned base = 0;
      for (int d = 0; d < 3; ++d) {
        if (rz && d == 1) {  // the y stencil is node 0 (kernels::store_stencils)
          b[d] = 0;
          continue;
        }
        const auto f = static_cast<std::int64_t>(first_node(x[d][p], inv_h, GimpShape::kShift));
        b[d] = f >> SparseGrid::kBlockBits;
        base |= static_cast<unsigned>(f & (SparseGrid::kBlock - 1)) << (2 * d);
      }
      keys[p] = SparseGrid::key(b[0], b[1], b[2]);
      bases.push_back(static_cast<std::uint8_t>(base));
    }
    grid.assign(keys, {}, ids);
    for (auto& f : node) {
      f.resize(grid.nodes().px.size());
      for (double& a : f) a = v(rng) * std::pow(10.0, e(rng));
    }
  }

  // One G2P over every block (FLIP/PIC blend with a filtered velocity when `filtered`), the
  // shared lanes when `shared`; the velocities, displacements and the particle order.
  std::vector<double> g2p(bool shared, bool filtered, std::vector<std::uint32_t>& order) const {
    const std::size_t n = x[0].size();
    std::vector<double> out(6 * n);
    for (std::size_t p = 0; p < n; ++p) {
      for (int d = 0; d < 3; ++d) out[d * n + p] = 0.1 * (d + 1) + 1e-3 * static_cast<double>(p);
    }
    G2PParticles in{};
    in.x = x[0].data();
    in.y = x[1].data();
    in.z = x[2].data();
    in.size0 = size0.data();
    in.vx = out.data();
    in.vy = out.data() + n;
    in.vz = out.data() + 2 * n;
    in.dx = out.data() + 3 * n;
    in.dy = out.data() + 4 * n;
    in.dz = out.data() + 5 * n;
    in.inv_h = inv_h;
    in.dt_velocity = 1e-7;
    in.dt_position = 1.1e-7;
    in.pic_fraction = filtered ? 0.3 : 0.0;
    if (filtered) {
      in.fvx = node[6].data();
      in.fvy = node[7].data();
      in.fvz = node[8].data();
    }
    in.stencil = recomputed(shared);
    SparseGrid::Nodes nodes = grid.nodes();
    std::vector<double>* const fields[6] = {&nodes.fx, &nodes.fy, &nodes.fz,
                                            &nodes.px, &nodes.py, &nodes.pz};
    for (int f = 0; f < 6; ++f) *fields[f] = node[f];
    G2PWindow win;
    for (std::uint32_t b = 0; b < grid.shared_blocks(); ++b) {
      g2p_block<GimpShape>(in, grid.owned(b), grid.coord(b), grid.neighbours(b), nodes, win,
                           [&](std::size_t p, const double(&)[3]) {
                             order.push_back(static_cast<std::uint32_t>(p));
                           });
    }
    return out;
  }

  StencilCache recomputed(bool shared) const {
    StencilCache c;
    c.mode = StencilCache::kRecompute;
    for (int d = 0; d < 3; ++d) c.x[d] = x[d].data();
    c.size0 = size0.data();
    c.inv_h = inv_h;
    c.axisymmetric = rz;
    c.shared_lanes = shared;
    return c;
  }

  // The velocity gradient over every block with node velocities node[3..5]: density, strain
  // and spin increments and L (APIC's columns), in that order.
  std::vector<double> gradient(bool shared) const {
    const std::size_t n = x[0].size();
    std::vector<double> out(19 * n, 1.0);
    GradientParticles in{};
    in.x = x[0].data();
    in.y = x[1].data();
    in.z = x[2].data();
    in.size0 = size0.data();
    double* col[19];
    for (int k = 0; k < 19; ++k) col[k] = out.data() + k * n;
    in.rho = col[0];
    in.exx = col[1], in.eyy = col[2], in.ezz = col[3], in.exy = col[4], in.eyz = col[5];
    in.exz = col[6], in.wxy = col[7], in.wyz = col[8], in.wxz = col[9];
    for (int k = 0; k < 9; ++k) in.vgrad[k] = col[10 + k];
    in.inv_h = inv_h;
    in.dt = 1e-7;
    in.stencil = recomputed(shared);
    SparseGrid::Nodes nodes = grid.nodes();
    nodes.px = node[3], nodes.py = node[4], nodes.pz = node[5];
    GradientWindow win;
    for (std::uint32_t b = 0; b < grid.shared_blocks(); ++b) {
      if (rz) {
        velocity_gradient_block<GimpShape, true>(in, grid.owned(b), grid.coord(b),
                                                 grid.neighbours(b), nodes, win);
      } else {
        velocity_gradient_block<GimpShape>(in, grid.owned(b), grid.coord(b), grid.neighbours(b),
                                           nodes, win);
      }
    }
    return out;
  }
};

void expect_same_bits(const std::vector<double>& one, const std::vector<double>& shared,
                      std::size_t n) {
  ASSERT_EQ(one.size(), shared.size());
  for (std::size_t i = 0; i < one.size(); ++i) {
    ASSERT_EQ(std::memcmp(&one[i], &shared[i], sizeof(double)), 0)
        << "value " << i % n << " of column " << i / n << ": " << one[i] << " vs " << shared[i];
  }
}

TEST(SharedStencilLanes, RunsShareAStencilAndVisitEveryParticleOnce) {
  const Cloud c;
  const StencilCache cache = c.recomputed(true);
  std::vector<int> seen(c.x[0].size(), 0);
  std::size_t runs = 0, points = 0;
  for (std::uint32_t b = 0; b < c.grid.shared_blocks(); ++b) {
    for_each_shared_run<false>(cache, c.grid.owned(b),
                               [&](const double*, unsigned base, const std::uint8_t* off,
                                   const std::uint32_t* idx, int count) {
                                 ASSERT_GE(count, 1);
                                 ASSERT_LE(count, kStencilBatch);
                                 ++runs;
                                 for (int k = 0; k < count; ++k) {
                                   ++seen[idx[k]];
                                   ++points;
                                   EXPECT_EQ(c.bases[idx[k]], base) << "particle " << idx[k];
                                   EXPECT_EQ(off[k], base) << "particle " << idx[k];
                                 }
                               });
  }
  for (std::size_t p = 0; p < seen.size(); ++p) EXPECT_EQ(seen[p], 1) << "particle " << p;
  // The lattice puts 8 points at each of its 96 stencil bases, the 40 scattered points make up
  // to 40 runs of their own: (768 + 40) / (96 + 40) = 5.9 points per run at least. In the
  // lists' order (by id, scrambled here) it would be about 1.
  EXPECT_GT(static_cast<double>(points) / static_cast<double>(runs), 5.5);
}

void check_g2p(bool filtered) {
  const Cloud c;
  std::vector<std::uint32_t> order_one, order_shared;
  const std::vector<double> one = c.g2p(false, filtered, order_one);
  const std::vector<double> shared = c.g2p(true, filtered, order_shared);
  // Every particle once; the order differs (by stencil base), the values must not.
  std::sort(order_one.begin(), order_one.end());
  std::sort(order_shared.begin(), order_shared.end());
  ASSERT_EQ(order_one, order_shared);
  ASSERT_EQ(order_one.size(), c.x[0].size());
  expect_same_bits(one, shared, c.x[0].size());
}

TEST(SharedStencilLanes, G2PMatchesOneParticleAtATimeFlip) {
  check_g2p(false);
}

TEST(SharedStencilLanes, G2PMatchesOneParticleAtATimeFilteredBlend) {
  check_g2p(true);
}

TEST(SharedStencilLanes, VelocityGradientMatchesOneParticleAtATime) {
  const Cloud c;
  expect_same_bits(c.gradient(false), c.gradient(true), c.x[0].size());
}

TEST(SharedStencilLanes, AxisymmetricVelocityGradientMatchesOneParticleAtATime) {
  const Cloud c(true);
  expect_same_bits(c.gradient(false), c.gradient(true), c.x[0].size());
}

}  // namespace
