// Fragment search (MPM paper Sec. 4.1.2; BA95 Sec. 4.4) on constructed cases with known answers,
// and its independence from particle order.

#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include <Eigen/Geometry>

#include "shatter/fracture/counter_rng.hpp"
#include "shatter/fracture/fragments.hpp"
#include "unit/fracture/lattice.hpp"

namespace shatter {
namespace {

constexpr double kD = 1.0e-3;  // lattice spacing, m

FragmentSearchSpec method(const char* name) {
  FragmentSearchSpec s;
  s.method = name;
  return s;
}

// Two lattice balls of radius 5 spacings, 4 spacings apart at the closest, with different
// particle masses so that swapped or merged fragments show in the masses.
std::vector<test::Point> two_balls(double& mass_a, double& mass_b) {
  std::vector<test::Point> pts;
  mass_a = mass_b = 0.0;
  for (int ball = 0; ball < 2; ++ball) {
    const double cx = ball == 0 ? 5.0 : 19.0;
    auto b = test::lattice(25, 11, 11, kD, [&](int i, int j, int k) {
      const double dx = i - cx, dy = j - 5.0, dz = k - 5.0;
      return dx * dx + dy * dy + dz * dz <= 25.0;
    });
    for (auto& p : b) {
      p.mass = ball == 0 ? 2.0e-3 : 3.0e-3;
      (ball == 0 ? mass_a : mass_b) += p.mass;
      pts.push_back(p);
    }
  }
  return pts;
}

TEST(FragmentSearch, TwoSeparatedBallsAreTwoFragmentsWithExactMasses) {
  // Every point is intact; all of each ball, its partly filled surface cells included, must be
  // found (masses compared to round-off of the sums: relative 1e-14).
  double ma = 0, mb = 0;
  const auto pts = two_balls(ma, mb);
  for (const char* m : {"grid_density", "friends_of_friends"}) {
    ParticleStore s = test::make_store(pts);
    const FragmentCatalogue cat = find_fragments(s, method(m));
    ASSERT_EQ(cat.fragments.size(), 2U) << m;
    // Ball b is heavier (3 g per point), so it is fragment 0.
    EXPECT_NEAR(cat.fragments[0].mass, mb, 1e-14 * mb) << m;
    EXPECT_NEAR(cat.fragments[1].mass, ma, 1e-14 * ma) << m;
    EXPECT_EQ(cat.dust_mass, 0.0) << m;
    EXPECT_NEAR(cat.fragments[0].centre.x(), 19.0 * kD, 1e-15) << m;
    for (std::size_t p = 0; p < pts.size(); ++p)
      EXPECT_EQ(s.col(IField::fragment)[p], s.col(Field::x)[p] > 12.0 * kD ? 0 : 1);
  }
}

TEST(FragmentSearch, DumbbellSplitsAtAOnePointNeckByTheExtendableRule) {
  // Two 8^3 cubes joined by a neck one point thick and two points long (i = 8, 9). The neck sits
  // in cells holding 2 of 8 points, below the extendable ratio 0.5, so it cannot join the cubes:
  // grid_density gives two fragments of 512 + 1 points each (each neck point joins its nearer
  // cube). Plain friends-of-friends (BA95) links everything into one fragment of 1026.
  const auto pts = test::lattice(
      18, 8, 8, kD, [](int i, int j, int k) { return i < 8 || i >= 10 || (j == 3 && k == 3); });
  ASSERT_EQ(pts.size(), 1026U);
  ParticleStore s = test::make_store(pts);
  const FragmentCatalogue grid = find_fragments(s, method("grid_density"));
  ASSERT_EQ(grid.fragments.size(), 2U);
  EXPECT_EQ(grid.fragments[0].particles, 513U);
  EXPECT_EQ(grid.fragments[1].particles, 513U);
  EXPECT_EQ(grid.fragments[0].mass, 513.0);
  for (std::size_t p = 0; p < pts.size(); ++p) {
    const bool left = s.col(Field::x)[p] < 8.5 * kD;
    // The lighter-index tie is broken by first particle in id order: the left cube is fragment 0.
    EXPECT_EQ(s.col(IField::fragment)[p], left ? 0 : 1) << "x = " << s.col(Field::x)[p];
  }
  const FragmentCatalogue fof = find_fragments(s, method("friends_of_friends"));
  ASSERT_EQ(fof.fragments.size(), 1U);
  EXPECT_EQ(fof.fragments[0].particles, 1026U);
}

TEST(FragmentSearch, FailedShellAroundIntactCoreGivesCorePlusOneFailedLayer) {
  // A 12^3 block: the inner 8^3 intact, a 2-point shell failed (D = 1). The fragment is the core
  // plus the failed points within the linking length 1.5 d of it: 6 x 64 face neighbours and
  // 12 x 8 edge neighbours (distance sqrt(2) d); corner points (sqrt(3) d) are not. So
  // 512 + 384 + 96 = 992 points, the other 736 shell points are dust. Counted exactly.
  auto pts = test::lattice(12, 12, 12, kD, [](int, int, int) { return true; });
  for (auto& p : pts) {
    const auto inside = [](double c) { return c > 1.5 * kD && c < 9.5 * kD; };
    p.damage = inside(p.x) && inside(p.y) && inside(p.z) ? 0.0 : 1.0;
  }
  for (const char* m : {"grid_density", "friends_of_friends"}) {
    ParticleStore s = test::make_store(pts);
    const FragmentCatalogue cat = find_fragments(s, method(m));
    ASSERT_EQ(cat.fragments.size(), 1U) << m;
    EXPECT_EQ(cat.fragments[0].particles, 992U) << m;
    EXPECT_EQ(cat.dust_mass, 1728.0 - 992.0) << m;
    EXPECT_EQ(cat.total_mass, 1728.0) << m;
  }
}

TEST(FragmentSearch, StaticStrengthPrePassCutsAStressedPlane) {
  // BA95 Sec. 4.4: undamaged points whose largest principal tension exceeds the static strength
  // count as failed. A 10x4x4 bar with the plane i = 5 under 10 MPa tension (strength 5 MPa)
  // splits into two; without the pre-pass it is one fragment. The plane becomes the veneer; its
  // points are equidistant (d) from both parts, so the tie goes to the lower label, the left part
  // found first: 5 x 16 + 16 = 96 and 4 x 16 = 64 points.
  auto pts = test::lattice(10, 4, 4, kD, [](int, int, int) { return true; });
  ParticleStore s = test::make_store(pts);
  s.require(kStress);
  for (std::size_t p = 0; p < pts.size(); ++p)
    if (std::abs(s.col(Field::x)[p] - 5.0 * kD) < 0.1 * kD) s.col(Field::sxx)[p] = 10e6;
  FragmentSearchSpec spec = method("friends_of_friends");
  EXPECT_EQ(find_fragments(s, spec).fragments.size(), 1U);
  spec.static_strength = 5e6;
  const FragmentCatalogue cat = find_fragments(s, spec);
  ASSERT_EQ(cat.fragments.size(), 2U);
  EXPECT_EQ(cat.fragments[0].particles, 96U);
  EXPECT_EQ(cat.fragments[1].particles, 64U);
}

TEST(FragmentKinematics, SpinningRigidBodyRecoversOmegaToRoundOff) {
  // Eq. 20 on a rigid motion v = V + omega x (x - x_c) of an irregular body with unequal masses:
  // L_c = J_c omega holds exactly, so omega = J_c^-1 L_c must come back to round-off. Relative
  // 1e-12: the sums over 1e3 points and the 3x3 solve each lose a few ulp times cond(J) ~ 10.
  auto pts = test::lattice(12, 9, 7, kD, [](int i, int j, int k) { return i + j + 2 * k < 22; });
  double m_total = 0.0;
  Eigen::Vector3d com = Eigen::Vector3d::Zero();
  for (std::size_t p = 0; p < pts.size(); ++p) {
    pts[p].mass = 1.0e-3 * (1.0 + 0.5 * counter_uniform(1, p, 0));
    m_total += pts[p].mass;
    com += pts[p].mass * Eigen::Vector3d(pts[p].x, pts[p].y, pts[p].z);
  }
  com /= m_total;
  const Eigen::Vector3d omega(120.0, -45.0, 300.0), v0(10.0, -2.0, 0.5);
  for (auto& p : pts) {
    const Eigen::Vector3d v = v0 + omega.cross(Eigen::Vector3d(p.x, p.y, p.z) - com);
    p.vx = v.x();
    p.vy = v.y();
    p.vz = v.z();
  }
  ParticleStore s = test::make_store(pts);
  const FragmentCatalogue cat = find_fragments(s, method("grid_density"));
  ASSERT_EQ(cat.fragments.size(), 1U);
  const Fragment& f = cat.fragments[0];
  EXPECT_NEAR((f.omega - omega).norm(), 0.0, 1e-12 * omega.norm());
  EXPECT_NEAR((f.velocity - v0).norm(), 0.0, 1e-12 * v0.norm());
  EXPECT_NEAR((f.centre - com).norm(), 0.0, 1e-15);
  EXPECT_NEAR((f.momentum - m_total * v0).norm(), 0.0, 1e-12 * m_total * v0.norm());
  EXPECT_NEAR((f.angular_momentum - f.inertia * omega).norm(), 0.0,
              1e-12 * f.angular_momentum.norm());
}

TEST(FragmentKinematics, EquivalentEllipsoidOfALatticeEllipsoid) {
  // A lattice ellipsoid with semi-axes 10, 6, 4 spacings: the equivalent ellipsoid from the
  // inertia (each point a cube of its volume) must recover them to the staircase error of the
  // surface, about half a spacing over the axis: 5% of the smallest axis (4 d) is allowed.
  const auto pts = test::lattice(21, 13, 9, kD, [](int i, int j, int k) {
    const double x = (i - 10) / 10.0, y = (j - 6) / 6.0, z = (k - 4) / 4.0;
    return x * x + y * y + z * z <= 1.0;
  });
  ParticleStore s = test::make_store(pts);
  const FragmentCatalogue cat = find_fragments(s, method("friends_of_friends"));
  ASSERT_EQ(cat.fragments.size(), 1U);
  const auto& ax = cat.fragments[0].axes;
  EXPECT_NEAR(ax[0], 10.0 * kD, 0.5 * kD);
  EXPECT_NEAR(ax[1], 6.0 * kD, 0.3 * kD);
  EXPECT_NEAR(ax[2], 4.0 * kD, 0.2 * kD);
  EXPECT_NEAR(cat.fragments[0].volume, pts.size() * kD * kD * kD, 1e-12 * pts.size() * 1e-9);
}

// A damaged block: damage from a hash of the lattice index, with failed planes cutting it into
// pieces, plus scattered failed points.
std::vector<test::Point> cracked_block() {
  auto pts = test::lattice(24, 20, 16, kD, [](int, int, int) { return true; });
  for (std::size_t p = 0; p < pts.size(); ++p) {
    const int i = static_cast<int>(std::lround(pts[p].x / kD));
    const int j = static_cast<int>(std::lround(pts[p].y / kD));
    const double u = counter_uniform(9, p, 0);
    pts[p].damage = (i == 7 || i == 15 || j == 9 || u < 0.08) ? 1.0 : 0.3 * u;
    pts[p].mass = 1e-3 * (1.0 + u);
    pts[p].vx = u - 0.5;
    pts[p].vy = 0.1 * i;
    pts[p].vz = -0.2 * j;
  }
  return pts;
}

TEST(FragmentSearch, ShuffledParticleOrderGivesTheSameCatalogue) {
  // Everything is computed in id order, so the catalogues must be bit-identical, and every
  // particle id must carry the same fragment id.
  const auto pts = cracked_block();
  for (const char* m : {"grid_density", "friends_of_friends"}) {
    ParticleStore a = test::make_store(pts);
    ParticleStore b = test::shuffled(pts, 2024);
    const FragmentCatalogue ca = find_fragments(a, method(m));
    const FragmentCatalogue cb = find_fragments(b, method(m));
    ASSERT_GE(ca.fragments.size(), 6U) << m;  // the three cut planes make at least 6 pieces
    ASSERT_EQ(ca.fragments.size(), cb.fragments.size()) << m;
    EXPECT_EQ(ca.dust_mass, cb.dust_mass);
    for (std::size_t f = 0; f < ca.fragments.size(); ++f) {
      EXPECT_EQ(ca.fragments[f].mass, cb.fragments[f].mass) << m << " fragment " << f;
      EXPECT_EQ(ca.fragments[f].particles, cb.fragments[f].particles);
      EXPECT_EQ(ca.fragments[f].centre, cb.fragments[f].centre);
      EXPECT_EQ(ca.fragments[f].omega, cb.fragments[f].omega);
      if (f > 0) {
        EXPECT_GE(ca.fragments[f - 1].mass, ca.fragments[f].mass);
      }
    }
    std::map<std::int64_t, std::int64_t> by_id;
    for (std::size_t p = 0; p < pts.size(); ++p)
      by_id[a.col(IField::id)[p]] = a.col(IField::fragment)[p];
    for (std::size_t p = 0; p < pts.size(); ++p)
      ASSERT_EQ(by_id[b.col(IField::id)[p]], b.col(IField::fragment)[p]) << m;
  }
}

TEST(FragmentSearch, RejectsUnknownMethodAndTooLongLinks) {
  ParticleStore s =
      test::make_store(test::lattice(2, 2, 2, kD, [](int, int, int) { return true; }));
  EXPECT_THROW(find_fragments(s, method("dbscan")), std::invalid_argument);
  FragmentSearchSpec spec = method("grid_density");
  spec.cell_size = 2 * kD;
  spec.linking_length = 3 * kD;
  EXPECT_THROW(find_fragments(s, spec), std::invalid_argument);
}

}  // namespace
}  // namespace shatter
