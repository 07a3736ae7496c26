// The viscous weights' block (src/sph/weight_buffer.hpp): SphSolver::Impl::place_weights re-lays
// the weights in place after growing it, so growth must keep every double written so far, also
// past glibc's mmap threshold (where realloc moves pages rather than copying).

#include <cstddef>

#include <gtest/gtest.h>

#include "sph/weight_buffer.hpp"

namespace shatter::sph {
namespace {

// Exact in binary64: no product that a compiler could contract into an FMA at one call only.
double pattern(std::size_t i) {
  return static_cast<double>(i % 1021) + 0.25;
}

TEST(WeightBuffer, GrowthKeepsTheContentAndNeverShrinks) {
  WeightBuffer w;
  EXPECT_TRUE(w.empty());
  w.grow(100);
  ASSERT_EQ(w.size(), 100U);
  for (std::size_t i = 0; i < w.size(); ++i) w.data()[i] = pattern(i);
  // From a small block to one of 8 MiB (mmap'ed by glibc), then further.
  for (const std::size_t n : {std::size_t{1000}, std::size_t{1} << 20, std::size_t{3} << 20}) {
    const std::size_t old = w.size();
    w.grow(n);
    ASSERT_EQ(w.size(), n);
    for (std::size_t i = 0; i < old; ++i) ASSERT_EQ(w[i], pattern(i)) << "index " << i;
    for (std::size_t i = old; i < n; ++i) w.data()[i] = pattern(i);
  }
  const double* before = w.data();
  w.grow(10);  // smaller: nothing happens
  EXPECT_EQ(w.size(), std::size_t{3} << 20);
  EXPECT_EQ(w.data(), before);
  EXPECT_EQ(w[12345], pattern(12345));
}

TEST(WeightBuffer, GrowDiscardingGivesTheSizeAsked) {
  WeightBuffer w;
  w.grow(8);
  w.data()[7] = 1.0;
  w.grow_discarding(4);  // already large enough: kept
  EXPECT_EQ(w.size(), 8U);
  EXPECT_EQ(w[7], 1.0);
  w.grow_discarding(1 << 16);
  EXPECT_EQ(w.size(), std::size_t{1} << 16);
  w.data()[(1 << 16) - 1] = 2.0;  // writable to its end (ASan checks the bound)
  EXPECT_EQ(w[(1 << 16) - 1], 2.0);
}

}  // namespace
}  // namespace shatter::sph
