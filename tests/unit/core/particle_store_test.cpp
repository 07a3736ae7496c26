#include <gtest/gtest.h>

#include <numeric>

#include "shatter/core/particles.hpp"

using namespace shatter;

TEST(ParticleStore, OnlyRegisteredColumnsExist) {
  ParticleStore s;
  s.require(Field::x);
  s.add_group(0, 10);
  EXPECT_TRUE(s.has(Field::x));
  EXPECT_FALSE(s.has(Field::damage));
  EXPECT_EQ(s.col(Field::x).size(), 10u);
  EXPECT_THROW((void)s.col(Field::damage), std::logic_error);
  // Registering later sizes the column to the particles already present.
  s.require(Field::damage);
  EXPECT_EQ(s.col(Field::damage).size(), 10u);
}

TEST(ParticleStore, ColumnsAreCacheLineAligned) {
  ParticleStore s;
  s.require({Field::x, Field::y, Field::mass});
  s.add_group(0, 1001);
  for (const Field f : {Field::x, Field::y, Field::mass}) {
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(s.col(f).data()) % 64, 0u) << name_of(f);
  }
}

TEST(ParticleStore, GroupsAreContiguousRanges) {
  ParticleStore s;
  s.require(Field::x);
  const Range a = s.add_group(0, 3);
  const Range b = s.add_group(1, 5);
  EXPECT_EQ(a.begin, 0u);
  EXPECT_EQ(a.end, 3u);
  EXPECT_EQ(b.begin, 3u);
  EXPECT_EQ(b.end, 8u);
  ASSERT_EQ(s.groups().size(), 2u);
  EXPECT_EQ(s.groups()[1].material, 1);
}

TEST(ParticleStore, PermuteMovesEveryColumnTogether) {
  ParticleStore s;
  s.require({Field::x, Field::mass});
  s.require(IField::id);
  s.add_group(0, 4);
  for (std::size_t p = 0; p < 4; ++p) {
    s.col(Field::x)[p] = static_cast<double>(p);
    s.col(Field::mass)[p] = 10.0 * static_cast<double>(p);
    s.col(IField::id)[p] = static_cast<std::int64_t>(p);
  }
  const std::vector<std::uint32_t> order = {3, 1, 0, 2};
  s.permute(order);
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(s.col(Field::x)[k], static_cast<double>(order[k]));
    EXPECT_EQ(s.col(Field::mass)[k], 10.0 * static_cast<double>(order[k]));
    EXPECT_EQ(s.col(IField::id)[k], static_cast<std::int64_t>(order[k]));
  }
}

TEST(ParticleStore, RemoveKeepsOrderAndShrinksGroups) {
  ParticleStore s;
  s.require(Field::x);
  s.add_group(0, 3);
  s.add_group(1, 3);
  for (std::size_t p = 0; p < 6; ++p) s.col(Field::x)[p] = static_cast<double>(p);
  const std::vector<std::uint8_t> flags = {0, 1, 0, 1, 1, 0};
  EXPECT_EQ(s.remove_if(flags), 3u);
  ASSERT_EQ(s.size(), 3u);
  EXPECT_EQ(s.col(Field::x)[0], 0.0);
  EXPECT_EQ(s.col(Field::x)[1], 2.0);
  EXPECT_EQ(s.col(Field::x)[2], 5.0);
  EXPECT_EQ(s.groups()[0].range.end, 2u);
  EXPECT_EQ(s.groups()[1].range.begin, 2u);
  EXPECT_EQ(s.groups()[1].range.end, 3u);
}
