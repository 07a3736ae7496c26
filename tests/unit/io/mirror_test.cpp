#include "shatter/io/mirror.hpp"

#include <gtest/gtest.h>

#include "sample_store.hpp"

namespace shatter::io {
namespace {

TEST(Mirror, DoublesEachGroupAndFlipsTheNormalComponents) {
  ParticleStore half = test::sample_store(3, 2);
  half.require(FieldSet{Field::sxz, Field::sxy, Field::szz});
  half.col(Field::sxz)[0] = 5.0;
  half.col(Field::sxy)[0] = 7.0;
  half.col(Field::szz)[0] = 9.0;
  const ParticleStore full = mirrored(half, 2);  // plane z = 0
  ASSERT_EQ(full.size(), 10u);
  ASSERT_EQ(full.groups().size(), 2u);
  EXPECT_EQ(full.groups()[1].range.begin, 6u);
  EXPECT_EQ(full.groups()[1].material, 3);
  // Group 0: particles 0..2 then their images 3..5.
  EXPECT_EQ(full.col(Field::z)[3], -half.col(Field::z)[0]);
  EXPECT_EQ(full.col(Field::vz)[3], -half.col(Field::vz)[0]);
  EXPECT_EQ(full.col(Field::x)[3], half.col(Field::x)[0]);
  EXPECT_EQ(full.col(Field::vx)[3], half.col(Field::vx)[0]);
  EXPECT_EQ(full.col(Field::sxz)[3], -5.0);  // one z index: flips
  EXPECT_EQ(full.col(Field::szz)[3], 9.0);   // two z indices: keeps
  EXPECT_EQ(full.col(Field::sxy)[3], 7.0);   // no z index: keeps
  EXPECT_EQ(full.col(Field::mass)[3], half.col(Field::mass)[0]);
  // Ids stay unique.
  EXPECT_NE(full.col(IField::id)[3], full.col(IField::id)[0]);
  EXPECT_EQ(full.col(IField::body)[8], 1);
}

}  // namespace
}  // namespace shatter::io
