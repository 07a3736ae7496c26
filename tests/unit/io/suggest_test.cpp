#include "shatter/io/suggest.hpp"

#include <gtest/gtest.h>

namespace shatter::io {
namespace {

TEST(Suggest, EditDistanceCountsInsertionsDeletionsAndSubstitutions) {
  EXPECT_EQ(edit_distance("", ""), 0u);
  EXPECT_EQ(edit_distance("radius", "radius"), 0u);
  EXPECT_EQ(edit_distance("raduis", "radius"), 2u);
  EXPECT_EQ(edit_distance("radiu", "radius"), 1u);
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
}

TEST(Suggest, ClosestOnlyWhenPlausiblyATypo) {
  const std::vector<std::string> keys = {"radius", "centre", "velocity", "spacing"};
  EXPECT_EQ(closest("raduis", keys), "radius");
  EXPECT_EQ(closest("center", keys), "centre");
  EXPECT_EQ(closest("velocty", keys), "velocity");
  EXPECT_EQ(closest("colour", keys), "");
  EXPECT_EQ(did_you_mean("spaceing", keys), " (did you mean 'spacing'?)");
  EXPECT_EQ(did_you_mean("zzz", keys), "");
}

}  // namespace
}  // namespace shatter::io
