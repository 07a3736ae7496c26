// The fragment search in r-z (issue 31): points are rings about z in the half-plane y = 0, r = x,
// linked in the half-plane and reported as bodies of revolution. Hand-built sets with known
// answers: two separate annuli and an on-axis piece.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "shatter/fracture/fragments.hpp"
#include "unit/fracture/lattice.hpp"

namespace shatter {
namespace {

constexpr double kD = 1.0e-3;    // lattice spacing in the half-plane, m
constexpr double kRho = 2700.0;  // kg/m3

// The rings of the cells (i, k), i in [i0, i1), k in [k0, k1): r = (i + 1/2) d, z = k d, cross-
// section d^2, volume 2 pi r d^2 (as src/scene/lattice_rz.cpp fills a body), velocity (vr, 0, vz).
void add_rings(std::vector<test::Point>& pts, int i0, int i1, int k0, int k1, double vr,
               double vz) {
  for (int i = i0; i < i1; ++i)
    for (int k = k0; k < k1; ++k) {
      test::Point p;
      p.x = (i + 0.5) * kD;
      p.z = k * kD;
      p.volume = 2.0 * std::numbers::pi * p.x * kD * kD;
      p.mass = kRho * p.volume;
      p.vx = vr;
      p.vz = vz;
      pts.push_back(p);
    }
}

struct Expected {
  double mass = 0.0, pz = 0.0, mz = 0.0, jzz = 0.0;
};

Expected sums(const std::vector<test::Point>& pts, std::size_t begin, std::size_t end) {
  Expected e;
  for (std::size_t p = begin; p < end; ++p) {
    e.mass += pts[p].mass;
    e.pz += pts[p].mass * pts[p].vz;
    e.mz += pts[p].mass * pts[p].z;
    e.jzz += pts[p].mass * pts[p].x * pts[p].x;
  }
  return e;
}

FragmentSearchSpec rz_spec(const char* method) {
  FragmentSearchSpec s;
  s.method = method;
  s.axisymmetric = true;
  return s;
}

TEST(FragmentRings, TwoAnnuliAndAnOnAxisPieceAreThreeBodiesOfRevolution) {
  // On the axis: a cylinder r < 5d, 4d tall, moving down and expanding radially. Two annuli off
  // the axis: 10d <= r < 14d (level with the cylinder) and 18d <= r < 21d higher up, 4 and 4
  // spacings clear of their neighbours (the linking length is 1.5 spacings).
  std::vector<test::Point> pts;
  add_rings(pts, 0, 5, 0, 4, 50.0, -300.0);
  const std::size_t a = pts.size();
  add_rings(pts, 10, 14, 0, 4, 120.0, 40.0);
  const std::size_t b = pts.size();
  add_rings(pts, 18, 21, 10, 13, 0.0, 75.0);
  const Expected axis = sums(pts, 0, a), ring1 = sums(pts, a, b), ring2 = sums(pts, b, pts.size());
  for (const char* m : {"grid_density", "friends_of_friends"}) {
    ParticleStore s = test::shuffled(pts, 7);
    const FragmentCatalogue cat = find_fragments(s, rz_spec(m));
    ASSERT_TRUE(cat.axisymmetric) << m;
    ASSERT_EQ(cat.fragments.size(), 3U) << m;
    EXPECT_EQ(cat.dust_mass, 0.0) << m;
    // Largest first: masses go as r, so the outer annulus (3 x 3 rings at r ~ 19.5d) outweighs
    // the inner one (4 x 4 at r ~ 12d)? 9 x 19.5 = 175.5 < 16 x 12 = 192: inner, outer, axis.
    const Fragment &f0 = cat.fragments[0], &f1 = cat.fragments[1], &f2 = cat.fragments[2];
    // Masses: sums of the rings' 2 pi r masses, to the round-off of the sums (1e-14 relative).
    EXPECT_NEAR(f0.mass, ring1.mass, 1e-14 * ring1.mass) << m;
    EXPECT_NEAR(f1.mass, ring2.mass, 1e-14 * ring2.mass) << m;
    EXPECT_NEAR(f2.mass, axis.mass, 1e-14 * axis.mass) << m;
    // Bodies of revolution: centre and velocity on the axis, the z momentum exact, no spin; the
    // radial velocities (an expanding ring) carry no net momentum.
    const Expected* e[3] = {&ring1, &ring2, &axis};
    for (int k = 0; k < 3; ++k) {
      const Fragment& f = cat.fragments[static_cast<std::size_t>(k)];
      EXPECT_EQ(f.centre.x(), 0.0) << m;
      EXPECT_EQ(f.centre.y(), 0.0) << m;
      EXPECT_NEAR(f.centre.z(), e[k]->mz / e[k]->mass, 1e-15) << m;
      EXPECT_EQ(f.momentum.x(), 0.0) << m;
      EXPECT_NEAR(f.momentum.z(), e[k]->pz, 1e-13 * std::abs(e[k]->pz)) << m;
      EXPECT_NEAR(f.velocity.z(), e[k]->pz / e[k]->mass, 1e-12) << m;
      EXPECT_EQ(f.omega.norm(), 0.0) << m;
      EXPECT_NEAR(f.inertia(2, 2), e[k]->jzz, 1e-13 * e[k]->jzz) << m;
    }
    // Only the cylinder touches the axis; the annuli are rings (r-z cannot say how they break up
    // round the axis).
    EXPECT_FALSE(f0.touches_axis) << m;
    EXPECT_FALSE(f1.touches_axis) << m;
    EXPECT_TRUE(f2.touches_axis) << m;
    EXPECT_NEAR(f0.r_min, 10.5 * kD, 1e-15) << m;
    EXPECT_NEAR(f0.r_max, 13.5 * kD, 1e-15) << m;
    EXPECT_NEAR(f2.r_min, 0.5 * kD, 1e-15) << m;
  }
}

TEST(FragmentRings, AFailedLayerSplitsAnOnAxisCylinderAndOrderDoesNotMatter) {
  // A cylinder r < 6d, 13d tall with the rings of the layer z = 6d failed: two on-axis pieces (the
  // failed layer, equally near both, joins one of them as its veneer), and in any storage order
  // the same catalogue.
  std::vector<test::Point> pts;
  add_rings(pts, 0, 6, 0, 13, 0.0, 0.0);
  for (auto& p : pts)
    if (std::abs(p.z - 6.0 * kD) < 0.25 * kD) p.damage = 1.0;
  ParticleStore s1 = test::make_store(pts), s2 = test::shuffled(pts, 3);
  const FragmentCatalogue c1 = find_fragments(s1, rz_spec("grid_density"));
  const FragmentCatalogue c2 = find_fragments(s2, rz_spec("grid_density"));
  ASSERT_EQ(c1.fragments.size(), 2U);
  ASSERT_EQ(c2.fragments.size(), 2U);
  double total = 0.0;
  for (const auto& p : pts) total += p.mass;
  EXPECT_NEAR(c1.fragments[0].mass + c1.fragments[1].mass + c1.dust_mass, total, 1e-14 * total);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_TRUE(c1.fragments[k].touches_axis);
    EXPECT_EQ(c1.fragments[k].mass, c2.fragments[k].mass);
    EXPECT_EQ(c1.fragments[k].centre.z(), c2.fragments[k].centre.z());
  }
  // One piece above the failed layer, one below.
  EXPECT_GT(std::max(c1.fragments[0].centre.z(), c1.fragments[1].centre.z()), 6.0 * kD);
  EXPECT_LT(std::min(c1.fragments[0].centre.z(), c1.fragments[1].centre.z()), 6.0 * kD);
}

TEST(FragmentRings, TheThreeDimensionalSearchWouldLinkRingsAsPoints) {
  // Why the r-z flag exists: read as 3-D points, the rings' volumes (2 pi r d^2, up to 130 d^3
  // here) make the 3-D spacing cbrt(mean volume) several lattice spacings, and its linking length
  // bridges the 4-spacing gaps: the annuli and the cylinder come out as one lump.
  std::vector<test::Point> pts;
  add_rings(pts, 0, 5, 0, 4, 0.0, 0.0);
  add_rings(pts, 10, 14, 0, 4, 0.0, 0.0);
  add_rings(pts, 18, 21, 0, 3, 0.0, 0.0);
  ParticleStore s = test::make_store(pts);
  FragmentSearchSpec three_d;
  three_d.method = "friends_of_friends";
  EXPECT_LT(find_fragments(s, three_d).fragments.size(), 3U);
  ParticleStore s2 = test::make_store(pts);
  EXPECT_EQ(find_fragments(s2, rz_spec("friends_of_friends")).fragments.size(), 3U);
}

}  // namespace
}  // namespace shatter
