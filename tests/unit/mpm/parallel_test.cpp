// The rank-independence building blocks of docs/mpi.md: the exact sum and the Morton-curve
// decomposition (the MPI runs themselves are compared bitwise in tests/mpi).

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "shatter/grid/sparse_grid.hpp"
#include "shatter/parallel/decomposition.hpp"
#include "shatter/parallel/exact_sum.hpp"

namespace shatter {
namespace {

std::uint64_t bits(double v) {
  return std::bit_cast<std::uint64_t>(v);
}

// The same bits in any order and any split (tolerance: zero), and the correctly known value
// where plain summation loses it entirely.
TEST(ExactSum, OrderAndSplitDoNotChangeTheBits) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> mant(-1.0, 1.0);
  std::uniform_int_distribution<int> expo(-60, 60);
  std::vector<double> v(5000);
  for (double& x : v) x = std::ldexp(mant(rng), expo(rng));
  parallel::ExactSum a;
  for (double x : v) a.add(x);
  const double ref = a.value();
  std::shuffle(v.begin(), v.end(), rng);
  parallel::ExactSum b, c;
  for (std::size_t i = 0; i < v.size(); ++i) (i % 3 == 0 ? b : c).add(v[i]);
  b.add(c);
  EXPECT_EQ(bits(b.value()), bits(ref));
  // Naive summation of the shuffled terms differs from the exact value in general; the exact
  // sum agrees with a long double Kahan sum to its precision.
  long double s = 0.0L, comp = 0.0L;
  for (double x : v) {
    const long double y = x - comp;
    const long double t = s + y;
    comp = (t - s) - y;
    s = t;
  }
  EXPECT_NEAR(ref, static_cast<double>(s), 1e-15 * std::abs(ref) + 1e-300);
}

TEST(ExactSum, CancellationAndSubnormals) {
  parallel::ExactSum a;
  a.add(1e300);
  a.add(1.0);
  a.add(-1e300);
  EXPECT_EQ(a.value(), 1.0);  // plain doubles give 0
  parallel::ExactSum b;
  b.add(4.9406564584124654e-324);
  b.add(4.9406564584124654e-324);
  EXPECT_EQ(b.value(), 2 * 4.9406564584124654e-324);
  parallel::ExactSum c;
  c.add(-2.5);
  c.add(0.5);
  EXPECT_EQ(c.value(), -2.0);
  parallel::ExactSum d;
  d.add(std::nan(""));
  EXPECT_TRUE(std::isnan(d.value()));
}

TEST(Decomposition, CutsBalanceParticlesAndCoverEveryBlock) {
  std::vector<std::pair<std::uint64_t, std::int64_t>> w;
  for (int x = 0; x < 8; ++x) {
    for (int y = 0; y < 8; ++y) w.emplace_back(SparseGrid::key(x, y, 0), 10);
  }
  parallel::Decomposition d;
  d.build(w, 4);
  std::vector<int> count(4, 0);
  for (const auto& [k, n] : w) {
    const int r = d.rank_of(k);
    ASSERT_GE(r, 0);
    ASSERT_LT(r, 4);
    count[static_cast<std::size_t>(r)] += static_cast<int>(n);
  }
  // 64 blocks of 10 particles: 160 per rank exactly (cuts fall between blocks)
  for (int c : count) EXPECT_EQ(c, 160);
  // any key maps somewhere, also far from the particles
  const int far = d.rank_of(SparseGrid::key(-1000, 5000, -7));
  EXPECT_GE(far, 0);
  EXPECT_LT(far, 4);
}

// A ghost block beyond a plane and its partner share the owner.
TEST(Decomposition, BlocksNearAMirrorPlaneShareTheOwner) {
  std::vector<std::pair<std::uint64_t, std::int64_t>> w;
  for (int x = 0; x < 8; ++x) {
    for (int z = -1; z < 6; ++z) w.emplace_back(SparseGrid::key(x, 0, z), 1 + x * z * z);
  }
  parallel::Decomposition d;
  d.set_planes({{2, 0}});  // z = 0 at node 0: blocks z = -1 and z = 0 within reach
  d.build(w, 3);
  for (int x = 0; x < 8; ++x) {
    EXPECT_EQ(d.rank_of(SparseGrid::key(x, 0, -1)), d.rank_of(SparseGrid::key(x, 0, 0)));
    EXPECT_TRUE(d.near_plane(SparseGrid::key(x, 0, -1)));
    EXPECT_TRUE(d.near_plane(SparseGrid::key(x, 0, 0)));
    EXPECT_FALSE(d.near_plane(SparseGrid::key(x, 0, 2)));
  }
}

}  // namespace
}  // namespace shatter
