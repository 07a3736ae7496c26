// BA99's bound remnant with the dust points as bodies (bound_remnant_with_dust), on hand-built
// configurations in G = 1 units: a shattered body with no fragment at all, a bound dust pair
// beside an escaping point, dust joining a fragment at 0.9 and not at 1.1 of escape speed, a
// self-bound bulk that outweighs an escaping largest fragment, and storage-order independence.
// The criterion is a strict inequality on exact numbers here, so the checks are exact (or to
// round-off of the sums, 1e-15).

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "shatter/fracture/bound_remnant.hpp"

namespace shatter {
namespace {

struct Point {
  double m;
  Eigen::Vector3d r, v;
};

// A store of dust points (fragment label -1), ids 0, 1, ... in the order given.
ParticleStore dust_store(const std::vector<Point>& pts) {
  ParticleStore s;
  s.require(FieldSet{Field::x, Field::y, Field::z, Field::vx, Field::vy, Field::vz, Field::mass});
  s.require(IField::id);
  s.require(IField::fragment);
  s.add_group(0, pts.size());
  for (std::size_t p = 0; p < pts.size(); ++p) {
    s.col(Field::mass)[p] = pts[p].m;
    s.col(Field::x)[p] = pts[p].r.x();
    s.col(Field::y)[p] = pts[p].r.y();
    s.col(Field::z)[p] = pts[p].r.z();
    s.col(Field::vx)[p] = pts[p].v.x();
    s.col(Field::vy)[p] = pts[p].v.y();
    s.col(Field::vz)[p] = pts[p].v.z();
    s.col(IField::id)[p] = static_cast<std::int64_t>(p);
    s.col(IField::fragment)[p] = -1;
  }
  return s;
}

FragmentCatalogue one_fragment(double m, Eigen::Vector3d r, Eigen::Vector3d v) {
  FragmentCatalogue c;
  Fragment f;
  f.mass = m;
  f.centre = r;
  f.velocity = v;
  c.fragments.push_back(f);
  return c;
}

// 27 dust points of mass 1 on a unit cube lattice, at rest: a body shattered to dust. No
// fragment seeds BA99's growth, but the bulk is bound to itself: all of it is the remnant
// (bound_remnant() on the same catalogue has nothing).
TEST(BoundRemnantDust, ShatteredBodyAtRestIsBoundWithoutAnyFragment) {
  std::vector<Point> pts;
  for (int i = -1; i <= 1; ++i) {
    for (int j = -1; j <= 1; ++j) {
      for (int k = -1; k <= 1; ++k)
        pts.push_back({1.0, {double(i), double(j), double(k)}, {0, 0, 0}});
    }
  }
  const ParticleStore s = dust_store(pts);
  const BoundRemnant r = bound_remnant_with_dust(FragmentCatalogue{}, s, 1.0);
  EXPECT_DOUBLE_EQ(r.mass, 27.0);
  EXPECT_EQ(r.dust_points, 27);
  EXPECT_TRUE(r.members.empty());
  EXPECT_EQ(r.seed, "self-bound bulk");
  EXPECT_EQ(bound_remnant(FragmentCatalogue{}, 1.0).mass, 0.0);
}

// Two points of mass 1 at rest, 1 apart (bound), and a light point 10 from their centre moving
// at 1.1 x the escape speed from mass 2 at 10 (sqrt(2 * 2 / 10)): the pair only. The same light
// point at 0.9 of it joins.
TEST(BoundRemnantDust, BoundDustPairKeepsSlowPointAndLosesFastOne) {
  const double ve = std::sqrt(2.0 * 2.0 / 10.0);
  for (const double f : {0.9, 1.1}) {
    const ParticleStore s = dust_store({{1.0, {-0.5, 0, 0}, {0, 0, 0}},
                                        {1.0, {0.5, 0, 0}, {0, 0, 0}},
                                        {1e-6, {0, 10, 0}, {0, f * ve, 0}}});
    const BoundRemnant r = bound_remnant_with_dust(FragmentCatalogue{}, s, 1.0);
    EXPECT_EQ(r.dust_points, f < 1.0 ? 3 : 2) << f;
    EXPECT_NEAR(r.mass, f < 1.0 ? 2.0 + 1e-6 : 2.0, 1e-15) << f;
  }
}

// A fragment of mass 1 and dust points of mass 1e-3 at distance 1: at 0.9 of the escape speed
// sqrt(2) a point joins the fragment, at 1.1 it does not; the members are the fragment's id.
TEST(BoundRemnantDust, DustJoinsTheLargestFragmentBelowEscapeSpeed) {
  const double ve = std::sqrt(2.0);
  ParticleStore s =
      dust_store({{1e-3, {1, 0, 0}, {0, 0.9 * ve, 0}}, {1e-3, {-1, 0, 0}, {0, 1.1 * ve, 0}}});
  const FragmentCatalogue cat = one_fragment(1.0, {0, 0, 0}, {0, 0, 0});
  const BoundRemnant r = bound_remnant_with_dust(cat, s, 1.0);
  EXPECT_EQ(r.members, (std::vector<std::int64_t>{0}));
  EXPECT_EQ(r.dust_points, 1);
  EXPECT_NEAR(r.mass, 1.001, 1e-15);
  EXPECT_NEAR(r.dust_mass, 1e-3, 1e-18);
  EXPECT_EQ(r.seed, "largest fragment");
}

// The largest (intact) fragment, mass 0.1, flies off at speed 10; the shattered bulk, 8 points
// of mass 1 on a unit cube at rest, is bound to itself and is the larger aggregate.
TEST(BoundRemnantDust, SelfBoundBulkOutweighsAnEscapingFragment) {
  std::vector<Point> pts;
  for (int i = 0; i < 8; ++i)
    pts.push_back({1.0, {double(i & 1), double(i >> 1 & 1), double(i >> 2)}, {0, 0, 0}});
  const ParticleStore s = dust_store(pts);
  const FragmentCatalogue cat = one_fragment(0.1, {5, 0, 0}, {10, 0, 0});
  const BoundRemnant r = bound_remnant_with_dust(cat, s, 1.0);
  EXPECT_DOUBLE_EQ(r.mass, 8.0);
  EXPECT_TRUE(r.members.empty());
  EXPECT_EQ(r.seed, "self-bound bulk");
}

// The dust is taken in id order, so a permuted store gives the same bits.
TEST(BoundRemnantDust, StorageOrderDoesNotChangeTheBits) {
  std::vector<Point> pts;
  for (int i = 0; i < 20; ++i) {
    const double t = 0.7 * i;
    pts.push_back({1.0 + 0.01 * i,
                   {std::cos(t) * (1 + 0.1 * i), std::sin(t), 0.05 * i},
                   {0.01 * std::sin(3 * t), 0.02 * std::cos(t), 0.0}});
  }
  ParticleStore a = dust_store(pts), b = dust_store(pts);
  std::vector<std::uint32_t> order(pts.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = std::uint32_t(order.size() - 1 - k);
  b.permute(order);
  const BoundRemnant ra = bound_remnant_with_dust(FragmentCatalogue{}, a, 1.0);
  const BoundRemnant rb = bound_remnant_with_dust(FragmentCatalogue{}, b, 1.0);
  EXPECT_GT(ra.dust_points, 1);
  EXPECT_EQ(ra.mass, rb.mass);
  EXPECT_EQ(ra.velocity, rb.velocity);
  EXPECT_EQ(ra.angular_momentum, rb.angular_momentum);
}

TEST(BoundRemnantDust, StoreWithoutLabelsIsRefused) {
  ParticleStore s;
  s.require(Field::mass);
  EXPECT_THROW(bound_remnant_with_dust(FragmentCatalogue{}, s, 1.0), std::invalid_argument);
}

}  // namespace
}  // namespace shatter
