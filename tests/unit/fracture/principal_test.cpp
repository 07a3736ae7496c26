// Principal values by Jacobi rotations (kernels/damage/principal.hpp) against Eigen's solver,
// and SIMD lanes against the scalar path.

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <random>

#include <Eigen/Eigenvalues>

#include "damage/principal.hpp"
#include "unit/fracture/lattice.hpp"

namespace shatter {
namespace {

Eigen::Matrix3d matrix_of(const double (&s)[6]) {
  Eigen::Matrix3d a;
  a << s[0], s[3], s[5], s[3], s[1], s[4], s[5], s[4], s[2];
  return a;
}

// Random stress tensors from 1 kPa to 10 GPa plus degenerate cases (triple root, double roots,
// pure shear, uniaxial, off-diagonal terms far below the diagonal).
std::vector<std::array<double, 6>> samples() {
  std::vector<std::array<double, 6>> out = {
      {1e8, 1e8, 1e8, 0, 0, 0},    {0, 0, 0, 0, 0, 0},
      {5e7, 0, 0, 0, 0, 0},        {-3e9, 1e6, 1e6, 0, 0, 0},
      {2e6, 2e6, -1e6, 0, 0, 0},   {0, 0, 0, 4e7, 0, 0},
      {1e8, 1e8, 1e8, 1e-3, 0, 0}, {7e7, 7e7, 7e7, 1e7, 1e7, 1e7},
      {1, 2, 3, 0.5, -0.25, 0.125}};
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 2000; ++i) {
    const double scale = std::pow(10.0, 3.0 + 7.0 * (u(rng) + 1.0) / 2.0);
    std::array<double, 6> s{};
    for (double& v : s) v = scale * u(rng);
    out.push_back(s);
  }
  return out;
}

constexpr double kEps = 2.220446049250313e-16;

// Jacobi rotations are backward stable: eigenvalues within a few eps ||A|| however close they are
// (measured worst 7.2 eps ||A|| over 2e5 random tensors and 2e4 rotated near-double roots).
double tolerance(const Eigen::Matrix3d& a) {
  return 16.0 * kEps * std::max(a.norm(), 1e-300);
}

TEST(PrincipalValues, MatchEigenSolverToRoundOffOfTheNorm) {
  for (const auto& arr : samples()) {
    const double s[6] = {arr[0], arr[1], arr[2], arr[3], arr[4], arr[5]};
    const Eigen::Matrix3d a = matrix_of(s);
    const Eigen::Vector3d ref =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(a, Eigen::EigenvaluesOnly).eigenvalues();
    const auto pv = damage::principal_values(s);
    const double tol = tolerance(a);
    EXPECT_NEAR(pv.s1, ref[2], tol);
    EXPECT_NEAR(pv.s2, ref[1], tol);
    EXPECT_NEAR(pv.s3, ref[0], tol);
    EXPECT_GE(pv.s1, pv.s2 - tol);
    EXPECT_GE(pv.s2, pv.s3 - tol);
  }
}

TEST(PrincipalValues, SimdLanesEqualScalarPath) {
  // Only +, -, *, /, sqrt (correctly rounded on both paths) and min/max/select; the paths differ
  // only where GCC contracts a*b+c into an FMA in the scalar code (-ffp-contract=fast is GCC's
  // default), one rounding per contraction, so both are within the round-off bound of the solver
  // and of each other: 16 eps ||A||, as against Eigen.
  using B = test::Batch;
  constexpr std::size_t w = B::size;
  const auto all = samples();
  for (std::size_t base = 0; base + w <= all.size(); base += w) {
    alignas(64) double in[6][w];
    for (std::size_t l = 0; l < w; ++l)
      for (int c = 0; c < 6; ++c) in[c][l] = all[base + l][static_cast<std::size_t>(c)];
    const B s[6] = {B::load_aligned(in[0]), B::load_aligned(in[1]), B::load_aligned(in[2]),
                    B::load_aligned(in[3]), B::load_aligned(in[4]), B::load_aligned(in[5])};
    const auto pv = damage::principal_values(s);
    alignas(64) double s1[w], s3[w];
    pv.s1.store_aligned(s1);
    pv.s3.store_aligned(s3);
    for (std::size_t l = 0; l < w; ++l) {
      const double sc[6] = {in[0][l], in[1][l], in[2][l], in[3][l], in[4][l], in[5][l]};
      const auto ref = damage::principal_values(sc);
      const double tol = tolerance(matrix_of(sc));
      EXPECT_NEAR(s1[l], ref.s1, tol);
      EXPECT_NEAR(s3[l], ref.s3, tol);
    }
  }
}

TEST(PrincipalValues, SettledSweepsKeepTheFourSweepsBits) {
  // principal_values stops rotating once no later rotation can change the diagonal
  // (detail::diagonal_settled, after any rotation of the second sweep on); it must give the bits
  // of the four sweeps (kAllSweeps) in every
  // lane. Tensors: the samples above, and random ones from nearly diagonal (off-diagonal terms
  // 1e-14-1 of the diagonal), r-z-like (a_xz = a_yz = 0), near double roots and a pressure shift,
  // so that batches stop after 1, 2 or 3 sweeps, inside a sweep, or run all four. Bound: bitwise
  // equality of s1, s2, s3, batch and scalar path; the counts show each exit was taken.
  using B = test::Batch;
  constexpr std::size_t w = B::size;
  auto all = samples();
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 16000; ++i) {
    const int kind = (i / 8) % 4;  // one kind per batch of 8
    const double scale = std::pow(10.0, 3.0 + 3.5 * (u(rng) + 1.0));
    const double off = kind == 0 ? 1.0 : std::pow(10.0, -7.0 * (u(rng) + 1.0));
    std::array<double, 6> s{};
    for (int k = 0; k < 3; ++k) s[static_cast<std::size_t>(k)] = scale * u(rng);
    for (int k = 3; k < 6; ++k) s[static_cast<std::size_t>(k)] = off * scale * u(rng);
    if (kind == 2) s[4] = s[5] = 0.0;
    if (kind == 3) s[1] = s[0] * (1.0 + 1e-9 * u(rng));
    const double p = (i % 3 == 0) ? 0.0 : scale * u(rng);
    for (int k = 0; k < 3; ++k) s[static_cast<std::size_t>(k)] -= p;
    all.push_back(s);
  }
  int exits[13] = {};
  for (std::size_t base = 0; base + w <= all.size(); base += w) {
    alignas(64) double in[6][w];
    for (std::size_t l = 0; l < w; ++l)
      for (int c = 0; c < 6; ++c) in[c][l] = all[base + l][static_cast<std::size_t>(c)];
    B s[6];
    for (int c = 0; c < 6; ++c) s[c] = B::load_aligned(in[c]);
    int rotations = -1;
    const auto a = damage::principal_values(s, &rotations);
    const auto b = damage::principal_values<B, true>(s);
    ++exits[rotations];
    alignas(64) double va[3][w], vb[3][w];
    a.s1.store_aligned(va[0]), a.s2.store_aligned(va[1]), a.s3.store_aligned(va[2]);
    b.s1.store_aligned(vb[0]), b.s2.store_aligned(vb[1]), b.s3.store_aligned(vb[2]);
    for (std::size_t l = 0; l < w; ++l) {
      const double sc[6] = {in[0][l], in[1][l], in[2][l], in[3][l], in[4][l], in[5][l]};
      const auto ca = damage::principal_values(sc);
      const auto cb = damage::principal_values<double, true>(sc);
      const double sa[3] = {ca.s1, ca.s2, ca.s3}, sb[3] = {cb.s1, cb.s2, cb.s3};
      for (int k = 0; k < 3; ++k) {
        ASSERT_EQ(std::bit_cast<std::uint64_t>(va[k][l]), std::bit_cast<std::uint64_t>(vb[k][l]))
            << "batch at " << base << " lane " << l << " value " << k;
        ASSERT_EQ(std::bit_cast<std::uint64_t>(sa[k]), std::bit_cast<std::uint64_t>(sb[k]))
            << "sample " << base + l << " value " << k;
      }
    }
  }
  EXPECT_GT(exits[3] + exits[6], 100);                // after 1 or 2 sweeps
  EXPECT_GT(exits[7] + exits[8] + exits[9], 100);     // in or after the third sweep
  EXPECT_GT(exits[10] + exits[11] + exits[12], 100);  // in the fourth
  EXPECT_GT(exits[4] + exits[5] + exits[7] + exits[8] + exits[10] + exits[11], 100);  // inside
}

}  // namespace
}  // namespace shatter
