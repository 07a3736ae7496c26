#pragma once
// Bitwise comparison of two particle stores, column by column (the determinism and equivalence
// tests: thread count, contact modes, resume).

#include <gtest/gtest.h>

#include <cstring>

#include "shatter/core/particles.hpp"

namespace shatter::test {

// Every column present in `a` equals the same column of `b` bit for bit; a failure names the
// column.
inline void expect_bitwise_equal_columns(const ParticleStore& a, const ParticleStore& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < kFieldCount; ++i) {
    const Field f = static_cast<Field>(i);
    if (!a.has(f)) continue;
    const auto ca = a.col(f);
    const auto cb = b.col(f);
    EXPECT_EQ(std::memcmp(ca.data(), cb.data(), ca.size_bytes()), 0) << name_of(f);
  }
}

}  // namespace shatter::test
