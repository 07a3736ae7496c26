// The pkdgrav hand-off's colour palette and packing-safe radius (src/fracture/ss_packing.cpp).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <set>
#include <vector>

#include "shatter/fracture/fragments.hpp"

namespace shatter {
namespace {

// Pairs (i < j) whose spheres overlap, by brute force: r_i + r_j > |x_i - x_j|.
std::size_t overlapping_pairs(const SsFile& ss) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < ss.records.size(); ++i) {
    for (std::size_t j = i + 1; j < ss.records.size(); ++j) {
      const double d = (ss.records[i].pos - ss.records[j].pos).norm();
      if (ss.records[i].radius + ss.records[j].radius > d) ++n;
    }
  }
  return n;
}

// A cubic lattice of spacing dx with each point's equal-volume radius (dx^3 = 4/3 pi r^3, so
// r = 0.620 dx > dx / 2: every face neighbour overlaps), as a fully failed body hands it over.
SsFile lattice(int n, double dx) {
  SsFile ss;
  const double r = std::cbrt(3.0 / (4.0 * std::numbers::pi)) * dx;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      for (int k = 0; k < n; ++k) {
        SsRecord rec;
        rec.pos = Eigen::Vector3d(i, j, k) * dx;
        rec.radius = r;
        ss.records.push_back(rec);
      }
    }
  }
  return ss;
}

TEST(SsPacking, LatticeOfEqualVolumeSpheresOverlapsAndPackingSafeRadiiDoNot) {
  SsFile ss = lattice(8, 0.01);
  // Face neighbours only (0.620 + 0.620 < sqrt 2): 3 x 8 x 8 x 7 pairs.
  EXPECT_EQ(overlapping_pairs(ss), 3u * 8u * 8u * 7u);
  EXPECT_EQ(apply_packing_safe_radius(ss), ss.records.size());
  EXPECT_EQ(overlapping_pairs(ss), 0u);
  // Half the spacing exactly (the lattice distances are exact in binary64 up to one rounding of
  // the coordinates: 1e-15 relative).
  for (const SsRecord& r : ss.records) EXPECT_NEAR(r.radius, 0.005, 1e-17);
}

TEST(SsPacking, RandomClusteredRecordsNeverOverlapAndSeparatedOnesKeepTheirRadius) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  SsFile ss;
  for (int c = 0; c < 5; ++c) {
    const Eigen::Vector3d centre(10.0 * c, 0.0, 0.0);
    for (int p = 0; p < 200; ++p) {
      SsRecord r;
      r.pos = centre + Eigen::Vector3d(u(rng), u(rng), u(rng)) * (0.1 + c);
      r.radius = 0.2 * std::abs(u(rng));
      ss.records.push_back(r);
    }
  }
  SsRecord far;  // alone, 1 km away: its radius stays
  far.pos = Eigen::Vector3d(1000.0, 0.0, 0.0);
  far.radius = 3.0;
  ss.records.push_back(far);
  ASSERT_GT(overlapping_pairs(ss), 0u);
  const std::size_t shrunk = apply_packing_safe_radius(ss);
  EXPECT_GT(shrunk, 0u);
  EXPECT_LT(shrunk, ss.records.size());
  EXPECT_EQ(overlapping_pairs(ss), 0u);
  EXPECT_EQ(ss.records.back().radius, 3.0);
}

TEST(SsPacking, RecordsOnAPlaneAreHandledQuickly) {
  // Fragment centres of a mirrored half model lie on the symmetry plane (z = 0 here); a grid
  // sized by the (zero) volume per point once made this take minutes for five records.
  SsFile ss;
  for (int i = 0; i < 5; ++i) {
    SsRecord r;
    r.pos = Eigen::Vector3d(0.003 * i, 0.001 * (i % 2), 0.0);
    r.radius = 0.004;
    ss.records.push_back(r);
  }
  EXPECT_EQ(apply_packing_safe_radius(ss), 5u);
  EXPECT_EQ(overlapping_pairs(ss), 0u);
}

TEST(SsPacking, ColoursStayInTheDocumentedPaletteAndAvoidThePlanetsColours) {
  const std::set<std::int32_t> reserved = {2, 5, 6, 7, 11};  // ssdefs.h: planets and the Sun
  const std::vector<std::int32_t>& palette = ss_palette();
  EXPECT_EQ(palette, (std::vector<std::int32_t>{3, 4, 8, 9, 10, 12, 13, 14, 15}));
  for (std::int64_t b = 0; b < 1000; ++b) {
    const std::int32_t c = ss_body_colour(b);
    EXPECT_EQ(reserved.count(c), 0u) << b;
    EXPECT_GE(c, 3);
    EXPECT_LE(c, 15);
    EXPECT_EQ(c, palette[static_cast<std::size_t>(b) % palette.size()]);  // wraps
  }
  EXPECT_EQ(ss_body_colour(0), 3);  // bodies 0 and 1 keep the colours of earlier files
  EXPECT_EQ(ss_body_colour(1), 4);
  EXPECT_EQ(ss_fragment_colour(-1), kSsDustColour);
  EXPECT_EQ(ss_fragment_colour(100000), ss_body_colour(100000));
}

TEST(SsPacking, RadiusChoiceByName) {
  EXPECT_EQ(ss_radius_by_name("equal_volume"), SsRadius::equal_volume);
  EXPECT_EQ(ss_radius_by_name("packing_safe"), SsRadius::packing_safe);
  EXPECT_THROW(ss_radius_by_name("tight"), std::invalid_argument);
}

}  // namespace
}  // namespace shatter
