// The named SPH pair terms (kernels/sph/terms.hpp) and the two gather passes
// (kernels/sph/gather.hpp): what each term must conserve or reproduce, term by term.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "sph/gather.hpp"

namespace shatter::kernels::sph {
namespace {

// A cubic lattice block of n^3 points of spacing s (mass rho0 s^3), h = 1.2 s, with all pairs
// within 2 h_ij listed by brute force: enough to drive the gather passes directly.
struct Block {
  std::vector<double> x, y, z, vx, vy, vz, m, rho, h, c;
  std::vector<std::vector<std::uint32_t>> nb;
  std::size_t centre = 0;
  Block(int n, double s, double rho0) {
    for (int a = 0; a < n; ++a) {
      for (int b = 0; b < n; ++b) {
        for (int k = 0; k < n; ++k) {
          x.push_back(a * s);
          y.push_back(b * s);
          z.push_back(k * s);
        }
      }
    }
    const std::size_t N = x.size();
    vx.assign(N, 0.0);
    vy.assign(N, 0.0);
    vz.assign(N, 0.0);
    m.assign(N, rho0 * s * s * s);
    rho.assign(N, rho0);
    h.assign(N, 1.2 * s);
    c.assign(N, 100.0);
    nb.resize(N);
    for (std::size_t i = 0; i < N; ++i) {
      for (std::size_t j = 0; j < N; ++j) {
        const double d[3] = {x[i] - x[j], y[i] - y[j], z[i] - z[j]};
        const double reach = h[i] + h[j];
        if (j != i && d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < reach * reach) {
          nb[i].push_back(static_cast<std::uint32_t>(j));
        }
      }
    }
    const int mid = n / 2;
    centre = static_cast<std::size_t>((mid * n + mid) * n + mid);
  }
  PairInputs inputs() const {
    return {x.data(),  y.data(), z.data(),   vx.data(), vy.data(),
            vz.data(), m.data(), rho.data(), h.data()};
  }
};

TEST(VelocityGradientTerm, LinearVelocityFieldGivesItsGradientInTheBulk) {
  // v = G x: Eq. 18 gives L = G M with M = sum_j V (x_j - x_i) (x) grad W_ij, which on the
  // interior of a cubic lattice at h = 1.2 s is 0.9816885670799698 I (computed independently in
  // CubicSpline.LatticeSumsAtTheDefaultSmoothingLength). So the pass must return M G dt.
  Block B(7, 0.01, 1000.0);
  const double G[3][3] = {{1.0, 0.3, -0.2}, {0.1, -0.5, 0.4}, {0.7, 0.2, 0.25}};
  for (std::size_t p = 0; p < B.x.size(); ++p) {
    const double X[3] = {B.x[p], B.y[p], B.z[p]};
    double* V[3] = {&B.vx[p], &B.vy[p], &B.vz[p]};
    for (int a = 0; a < 3; ++a) *V[a] = G[a][0] * X[0] + G[a][1] * X[1] + G[a][2] * X[2];
  }
  std::vector<double> deps[6], dspin[3];
  for (auto& v : deps) v.assign(B.x.size(), 0.0);
  for (auto& v : dspin) v.assign(B.x.size(), 0.0);
  std::vector<double> rho_new = B.rho;
  RateOutputs out;
  for (int k = 0; k < 6; ++k) out.deps[k] = deps[k].data();
  for (int k = 0; k < 3; ++k) out.dspin[k] = dspin[k].data();
  out.rho = rho_new.data();
  PairInputs in = B.inputs();
  // A short step, so that the pass's midpoint positions x + v dt / 2 and its rho^{n+1} in Eq. 18
  // differ from x^n and rho^n by ~|G| dt = 1e-8 relative: the tolerance.
  const double dt = 1e-8;
  const std::size_t i = B.centre;
  rates_particle(in, B.nb[i].data(), B.nb[i].size(), i, dt, out);
  const double k = 0.9816885670799698 * dt;
  const double tol = 1e-7 * dt;
  EXPECT_NEAR(deps[0][i], k * G[0][0], tol);
  EXPECT_NEAR(deps[1][i], k * G[1][1], tol);
  EXPECT_NEAR(deps[2][i], k * G[2][2], tol);
  EXPECT_NEAR(deps[3][i], k * 0.5 * (G[0][1] + G[1][0]), tol);
  EXPECT_NEAR(deps[4][i], k * 0.5 * (G[1][2] + G[2][1]), tol);
  EXPECT_NEAR(deps[5][i], k * 0.5 * (G[0][2] + G[2][0]), tol);
  EXPECT_NEAR(dspin[0][i], k * 0.5 * (G[0][1] - G[1][0]), tol);
  EXPECT_NEAR(dspin[1][i], k * 0.5 * (G[1][2] - G[2][1]), tol);
  EXPECT_NEAR(dspin[2][i], k * 0.5 * (G[0][2] - G[2][0]), tol);
  // Eq. 16: rho^{n+1} = rho^n - dt rho^n tr(M G), and 1 + tr deps = rho^n / rho^{n+1} exactly
  // (what MaterialModel::update assumes).
  const double tr_g = G[0][0] + G[1][1] + G[2][2];
  EXPECT_NEAR(rho_new[i], 1000.0 * (1.0 - k * tr_g), 1e-12 * 1000.0);
  EXPECT_NEAR(rho_new[i] * (1.0 + deps[0][i] + deps[1][i] + deps[2][i]), 1000.0, 1e-12 * 1000.0);
}

// Forces from pass 2 on every point of the block, for a given stress per point.
struct Forces {
  std::vector<double> ax, ay, az, heat, mu;
};
Forces forces(const Block& B, const std::vector<std::array<double, 6>>& sigma, double alpha,
              double beta) {
  const std::size_t N = B.x.size();
  std::vector<double> A[6];
  for (int k = 0; k < 6; ++k) {
    A[k].resize(N);
    for (std::size_t p = 0; p < N; ++p) A[k][p] = sigma[p][k] / (B.rho[p] * B.rho[p]);
  }
  ForceInputs f;
  for (int k = 0; k < 6; ++k) f.a_stress[k] = A[k].data();
  f.soundspeed = B.c.data();
  f.viscosity.alpha = alpha;
  f.viscosity.beta = beta;
  Forces F;
  for (auto* v : {&F.ax, &F.ay, &F.az, &F.heat, &F.mu}) v->assign(N, 0.0);
  const ForceOutputs out{F.ax.data(), F.ay.data(), F.az.data(), F.heat.data(), F.mu.data()};
  const PairInputs in = B.inputs();
  for (std::size_t i = 0; i < N; ++i)
    forces_particle(in, f, B.nb[i].data(), B.nb[i].size(), i, out);
  return F;
}

TEST(StressForceTerm, UniformStressExertsNoForceInTheBulkAndMomentumIsConserved) {
  Block B(7, 0.01, 1000.0);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1e6, 1e6);
  // Uniform stress: no force on an interior point (lattice symmetry: the pair terms cancel in
  // +/- pairs, so the sum is round-off of the largest pair term).
  std::vector<std::array<double, 6>> uniform(B.x.size(), {-3e6, 1e6, 2e6, 5e5, -4e5, 3e5});
  const Forces U = forces(B, uniform, 0.0, 0.0);
  const double scale = 4e6 / 1000.0 / 0.01;  // |sigma| / (rho s): a pair term's size
  EXPECT_NEAR(U.ax[B.centre], 0.0, 1e-12 * scale);
  EXPECT_NEAR(U.ay[B.centre], 0.0, 1e-12 * scale);
  EXPECT_NEAR(U.az[B.centre], 0.0, 1e-12 * scale);
  // Random stresses: Eq. 17's pair forces are equal and opposite, so sum m a = 0 to round-off.
  std::vector<std::array<double, 6>> random(B.x.size());
  for (auto& s : random) {
    for (double& v : s) v = u(rng);
  }
  const Forces R = forces(B, random, 0.0, 0.0);
  double p[3] = {0, 0, 0}, sum_abs = 0.0;
  for (std::size_t q = 0; q < B.x.size(); ++q) {
    p[0] += B.m[q] * R.ax[q];
    p[1] += B.m[q] * R.ay[q];
    p[2] += B.m[q] * R.az[q];
    sum_abs += B.m[q] * (std::abs(R.ax[q]) + std::abs(R.ay[q]) + std::abs(R.az[q]));
  }
  // Round-off: ~N_pairs x eps relative to the summed magnitudes; 1e-13 is ~500 eps.
  for (double v : p) EXPECT_LT(std::abs(v), 1e-13 * sum_abs);
}

TEST(ViscosityTerm, ActsOnApproachOnlyAndItsHeatEqualsTheWorkItDoes) {
  // Pi_ij = 0 for receding pairs.
  ViscosityCoefficients k;
  EXPECT_EQ(monaghan_viscosity(k, 1.0, 1e-4, 0.012, 100.0, 1000.0).pi, 0.0);
  const ViscousPair q = monaghan_viscosity(k, -1.0, 1e-4, 0.012, 100.0, 1000.0);
  EXPECT_GT(q.pi, 0.0);
  EXPECT_LT(q.mu, 0.0);

  // A random velocity field on the block: viscosity conserves momentum, and the heat it makes,
  // sum m du/dt, equals the kinetic energy it removes, -sum m v . a (Monaghan 1992, Eq. 4.4).
  Block B(6, 0.01, 1000.0);
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-10.0, 10.0);
  for (std::size_t p = 0; p < B.x.size(); ++p) {
    B.vx[p] = u(rng);
    B.vy[p] = u(rng);
    B.vz[p] = u(rng);
  }
  std::vector<std::array<double, 6>> zero(B.x.size(), {0, 0, 0, 0, 0, 0});
  const Forces F = forces(B, zero, 1.0, 2.0);
  double heat = 0.0, work = 0.0, mom[3] = {0, 0, 0}, scale = 0.0;
  for (std::size_t p = 0; p < B.x.size(); ++p) {
    heat += B.m[p] * F.heat[p];
    work += B.m[p] * (B.vx[p] * F.ax[p] + B.vy[p] * F.ay[p] + B.vz[p] * F.az[p]);
    mom[0] += B.m[p] * F.ax[p];
    mom[1] += B.m[p] * F.ay[p];
    mom[2] += B.m[p] * F.az[p];
    scale += B.m[p] * (std::abs(F.ax[p]) + std::abs(F.ay[p]) + std::abs(F.az[p]));
  }
  EXPECT_GT(heat, 0.0);                    // viscosity only ever heats
  EXPECT_NEAR(heat, -work, 1e-12 * heat);  // round-off over ~10^4 pair terms
  for (double v : mom) EXPECT_LT(std::abs(v), 1e-13 * scale);
}

TEST(GatherPasses, SimdLanesMatchTheScalarReference) {
  // Both passes with T = simd::Batch (what the solver runs) against T = double, on a jittered
  // lattice block (so pairs fall in both kernel branches and near the support's edge) with
  // random velocities, stresses and accelerations (viscosity active on about half the pairs).
  // The lanes sum the same terms in another order and take the kernel with the same
  // expressions, so the difference is summation round-off: ~60 terms per sum, each within a
  // few eps of its scalar twin, bounded by 1e-13 (~450 eps) of the sum of the terms' moduli,
  // which is estimated here by each output's largest modulus over the block times 10 (the
  // block's terms cancel by at most that much; measured: maximum differences 0.6-1.2e-15 of
  // this scale, at -O1 and -O3). mu_max is a maximum of the same expressions: equal to 1e-15
  // (FMA contraction may differ between the scalar and SIMD code).
  Block B(6, 0.01, 1000.0);
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const std::size_t N = B.x.size();
  for (std::size_t p = 0; p < N; ++p) {
    B.x[p] += 0.15 * 0.01 * u(rng);
    B.y[p] += 0.15 * 0.01 * u(rng);
    B.z[p] += 0.15 * 0.01 * u(rng);
    B.vx[p] = 10.0 * u(rng);
    B.vy[p] = 10.0 * u(rng);
    B.vz[p] = 10.0 * u(rng);
    B.h[p] *= 1.0 + 0.1 * u(rng);
    B.rho[p] *= 1.0 + 0.05 * u(rng);
  }
  // Lists again for the jittered points (brute force, ascending index).
  for (std::size_t i = 0; i < N; ++i) {
    B.nb[i].clear();
    for (std::size_t j = 0; j < N; ++j) {
      const double d[3] = {B.x[i] - B.x[j], B.y[i] - B.y[j], B.z[i] - B.z[j]};
      const double reach = B.h[i] + B.h[j];
      if (j != i && d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < reach * reach) {
        B.nb[i].push_back(static_cast<std::uint32_t>(j));
      }
    }
  }
  std::vector<double> A[6], a[3];
  for (auto& v : A) {
    v.resize(N);
    for (double& x : v) x = 1e3 * u(rng);  // sigma / rho^2 ~ 1e9 Pa / 1e6
  }
  for (auto& v : a) {
    v.resize(N);
    for (double& x : v) x = 1e6 * u(rng);
  }
  std::vector<std::size_t> offset(N + 1, 0);
  for (std::size_t i = 0; i < N; ++i) offset[i + 1] = offset[i] + B.nb[i].size();
  const PairInputs in = B.inputs();
  ForceInputs f;
  for (int k = 0; k < 6; ++k) f.a_stress[k] = A[k].data();
  f.soundspeed = B.c.data();

  struct Result {
    std::vector<double> ax, ay, az, heat, mu, pair_w, deps[6], dspin[3], rho, kick_heat;
  };
  auto run = [&](auto lanes) {
    using T = decltype(lanes);
    Result R;
    for (auto* v : {&R.ax, &R.ay, &R.az, &R.heat, &R.mu, &R.kick_heat}) v->assign(N, 0.0);
    // The weights as the forces pass packs them (the non-zero ones and a mask byte per group
    // of W entries), and spread back out, entry for entry, to compare the two paths.
    constexpr std::size_t W = Lanes<T>::width;
    std::vector<double> packed(offset[N] + 1, 0.0);
    std::vector<std::uint8_t> masks(offset[N] + N, 0);
    std::vector<std::size_t> w_at(N + 1, 0), mask_at(N + 1, 0);
    const ForceOutputs fo{R.ax.data(), R.ay.data(),   R.az.data(), R.heat.data(),
                          R.mu.data(), packed.data(), masks.data()};
    for (std::size_t i = 0; i < N; ++i) {
      const std::size_t count = B.nb[i].size();
      w_at[i + 1] =
          w_at[i] + forces_particle<T>(in, f, B.nb[i].data(), count, i, fo, w_at[i], mask_at[i]);
      mask_at[i + 1] = mask_at[i] + (count + W - 1) / W;
    }
    R.pair_w.assign(offset[N], 0.0);
    for (std::size_t i = 0; i < N; ++i) {
      std::size_t from = w_at[i];
      for (std::size_t k = 0; k < B.nb[i].size(); ++k) {
        if ((masks[mask_at[i] + k / W] >> (k % W)) & 1u) R.pair_w[offset[i] + k] = packed[from++];
      }
      EXPECT_EQ(from, w_at[i + 1]);
    }
    EXPECT_GT(w_at[N], 0u);  // some pairs approach, others not: both paths of the packing
    EXPECT_LT(w_at[N], offset[N]);
    RateOutputs ro;
    for (int k = 0; k < 6; ++k) ro.deps[k] = (R.deps[k] = std::vector<double>(N)).data();
    for (int k = 0; k < 3; ++k) ro.dspin[k] = (R.dspin[k] = std::vector<double>(N)).data();
    R.rho = B.rho;
    ro.rho = R.rho.data();
    KickHeating kick{packed.data(), masks.data(), a[0].data(),       a[1].data(),
                     a[2].data(),   1e-7,         R.kick_heat.data()};
    for (std::size_t i = 0; i < N; ++i) {
      EXPECT_EQ(rates_particle<T>(in, B.nb[i].data(), B.nb[i].size(), i, 1e-7, ro, kick, w_at[i],
                                  mask_at[i]),
                w_at[i + 1] - w_at[i]);
    }
    return R;
  };
  const Result S = run(0.0);
  const Result V = run(simd::Batch(0.0));
  auto compare = [](const std::vector<double>& s, const std::vector<double>& v, double rel,
                    const char* what) -> double {
    EXPECT_EQ(s.size(), v.size()) << what;
    double scale = 0.0, worst = 0.0;
    for (double x : s) scale = std::max(scale, std::abs(x));
    EXPECT_GT(scale, 0.0) << what;
    if (s.size() != v.size() || !(scale > 0.0)) return 1.0;
    for (std::size_t p = 0; p < s.size(); ++p) worst = std::max(worst, std::abs(s[p] - v[p]));
    EXPECT_LE(worst, rel * scale) << what;
    return worst / scale;
  };
  double worst = 0.0;
  for (const auto& [s, v, what] :
       {std::tuple{&S.ax, &V.ax, "ax"}, std::tuple{&S.ay, &V.ay, "ay"},
        std::tuple{&S.az, &V.az, "az"}, std::tuple{&S.heat, &V.heat, "heat"},
        std::tuple{&S.pair_w, &V.pair_w, "pair_w"}, std::tuple{&S.rho, &V.rho, "rho"},
        std::tuple{&S.kick_heat, &V.kick_heat, "kick heat"}}) {
    worst = std::max(worst, compare(*s, *v, 1e-12, what));
  }
  for (int k = 0; k < 6; ++k) worst = std::max(worst, compare(S.deps[k], V.deps[k], 1e-12, "deps"));
  for (int k = 0; k < 3; ++k) {
    worst = std::max(worst, compare(S.dspin[k], V.dspin[k], 1e-12, "dspin"));
  }
  compare(S.mu, V.mu, 1e-15, "mu");
  std::printf("SIMD (%zu lanes) against scalar: largest difference %.2e of the output's scale\n",
              simd::kWidth, worst);
}

// The compaction of a Verlet list in place: after each call the list's first m entries are
// exactly its pairs within support (distance2 < (h_i + h_j)^2) in ascending order, what a
// search without the skin lists, and the list holds the same entries as before. Several calls
// as the points move, each starting from the order the last one left (pairs entering and
// leaving support between calls), as the solver makes them.
TEST(GatherPasses, VerletListPartitionKeepsThePairsWithinSupportInAscendingOrder) {
  Block B(7, 1e-3, 2700.0);
  const std::size_t N = B.x.size();
  std::mt19937_64 rng(35);
  std::uniform_real_distribution<double> jitter(-0.15e-3, 0.15e-3);
  // Lists with a skin of 40 % of 2 h: the entries within 1.4 (h_i + h_j), ascending.
  std::vector<std::vector<std::uint32_t>> list(N);
  for (std::size_t i = 0; i < N; ++i) {
    for (std::size_t j = 0; j < N; ++j) {
      const double reach = 1.4 * (B.h[i] + B.h[j]);
      if (j != i && distance2(B.x[i] - B.x[j], B.y[i] - B.y[j], B.z[i] - B.z[j]) < reach * reach) {
        list[i].push_back(static_cast<std::uint32_t>(j));
      }
    }
  }
  std::vector<std::size_t> sorted(N);
  for (std::size_t i = 0; i < N; ++i) sorted[i] = list[i].size();
  std::vector<std::uint32_t> rest;
  std::size_t entered = 0;
  for (int call = 0; call < 6; ++call) {
    // Every third call at the same positions: nothing changes status (the list is left as it is).
    for (std::size_t p = 0; p < (call % 3 == 2 ? 0 : N); ++p) {
      B.x[p] += jitter(rng);
      B.y[p] += jitter(rng);
      B.z[p] += jitter(rng);
    }
    const PairInputs in = B.inputs();
    for (std::size_t i = 0; i < N; ++i) {
      std::vector<std::uint32_t> want;
      for (const std::uint32_t j : list[i]) {
        const double reach = B.h[i] + B.h[j];
        if (distance2(B.x[i] - B.x[j], B.y[i] - B.y[j], B.z[i] - B.z[j]) < reach * reach) {
          want.push_back(j);
        }
      }
      std::sort(want.begin(), want.end());
      for (std::size_t k = sorted[i]; k < list[i].size(); ++k) {
        entered += std::binary_search(want.begin(), want.end(), list[i][k]) ? 1 : 0;
      }
      std::vector<std::uint32_t> before = list[i];
      rest.assign(list[i].size() + 8, 0);
      const std::size_t m =
          partition_within_support(in, list[i].data(), list[i].size(), sorted[i], i, rest.data());
      ASSERT_EQ(m, want.size()) << "point " << i << ", call " << call;
      EXPECT_TRUE(std::equal(want.begin(), want.end(), list[i].begin()))
          << "point " << i << ", call " << call;
      std::vector<std::uint32_t> after = list[i];
      std::sort(before.begin(), before.end());
      std::sort(after.begin(), after.end());
      EXPECT_EQ(after, before) << "the list lost or gained entries: point " << i;
      sorted[i] = m;
    }
  }
  // The calls must have met pairs that came within support from the unsorted part.
  EXPECT_GT(entered, N);
}

}  // namespace
}  // namespace shatter::kernels::sph
