// The momentum enhancement beta = 1 + p_ej / p_imp (include/shatter/fracture/beta.hpp) and the
// ejecta launch record (ejecta_launch.hpp) on hand-built point sets whose answers are known
// exactly: masses and velocities are small integers, so every sum is exact and beta is compared
// with ==, not a tolerance.

#include <gtest/gtest.h>

#include <cstdint>
#include <numeric>
#include <random>
#include <vector>

#include "shatter/fracture/beta.hpp"
#include "shatter/fracture/ejecta_launch.hpp"

namespace shatter {
namespace {

struct P {
  Eigen::Vector3d x, v;
  double m;
  std::int64_t body;
};

ParticleStore store_of(const std::vector<P>& pts) {
  ParticleStore s;
  s.require(FieldSet{Field::x, Field::y, Field::z, Field::vx, Field::vy, Field::vz, Field::mass});
  s.require(IField::id);
  s.require(IField::body);
  s.add_group(0, pts.size());
  for (std::size_t p = 0; p < pts.size(); ++p) {
    s.col(Field::x)[p] = pts[p].x.x();
    s.col(Field::y)[p] = pts[p].x.y();
    s.col(Field::z)[p] = pts[p].x.z();
    s.col(Field::vx)[p] = pts[p].v.x();
    s.col(Field::vy)[p] = pts[p].v.y();
    s.col(Field::vz)[p] = pts[p].v.z();
    s.col(Field::mass)[p] = pts[p].m;
    s.col(IField::id)[p] = static_cast<std::int64_t>(p);
    s.col(IField::body)[p] = pts[p].body;
  }
  return s;
}

// Impact straight down (d = -z) at U = 4 m/s on the surface z = 0; the impactor is body 1.
BetaSpec down_spec() {
  BetaSpec s;
  s.impactor = 1;
  s.direction = -Eigen::Vector3d::UnitZ();
  s.impact_speed = 4.0;
  s.surface_point = Eigen::Vector3d::Zero();
  s.normal = Eigen::Vector3d::UnitZ();
  return s;
}

// After the impact: the impactor (2 kg, p_imp = 8 kg m/s) buried and at rest; two ejecta points
// above the surface flying up and out; target material below it pushed down and a slow point
// above it falling back (not ejecta: moving inward).
std::vector<P> after_impact() {
  using V = Eigen::Vector3d;
  return {
      {V(0, 0, -1), V(0, 0, 0), 2.0, 1},   // impactor, buried
      {V(1, 0, 2), V(3, 0, 1), 1.0, 0},    // ejecta: p . n = 1
      {V(-1, 0, 1), V(-1, 0, 2), 3.0, 0},  // ejecta: p . n = 6
      {V(0, 0, 1), V(0, 0, -1), 1.0, 0},   // above, falling back: not ejecta
      {V(0, 0, -2), V(0, 0, -8), 1.0, 0},  // target below, moving down
      {V(0, 0, 0), V(0, 0, 5), 1.0, 0},    // on the plane (not above): not ejecta
  };
}

TEST(Beta, HandBuiltEjectaGiveExactBeta) {
  const BetaSample b = measure_beta(store_of(after_impact()), down_spec());
  EXPECT_EQ(b.ejecta_mass, 4.0);
  EXPECT_EQ(b.ejecta_momentum, 7.0);    // 1 + 6 against d
  EXPECT_EQ(b.impactor_momentum, 8.0);  // 2 kg x 4 m/s
  EXPECT_EQ(b.beta, 1.0 + 7.0 / 8.0);
  // Not ejecta along d: falling point 1, target 8, on-plane point -5: 4 kg m/s.
  EXPECT_EQ(b.beta_target, 4.0 / 8.0);
}

TEST(Beta, NothingEjectedGivesBetaOne) {
  // Before the impact: the impactor above the surface moving in, the target at rest.
  using V = Eigen::Vector3d;
  const std::vector<P> before = {{V(0, 0, 3), V(0, 0, -4), 2.0, 1}, {V(0, 0, -1), V::Zero(), 5, 0}};
  const BetaSample b = measure_beta(store_of(before), down_spec());
  EXPECT_EQ(b.ejecta_mass, 0.0);
  EXPECT_EQ(b.beta, 1.0);
  // All the momentum is the impactor's, not ejecta: beta_target = 1 exactly.
  EXPECT_EQ(b.beta_target, 1.0);
}

TEST(Beta, MomentumConservedMakesBothMeasuresAgree) {
  // A state that conserved the impactor's 8 kg m/s along d: ejecta carry 7 up, so the rest must
  // carry 15 down; beta from the ejecta and from the target are then the same number.
  auto pts = after_impact();
  pts[4].v.z() = -19.0;  // target below: -8 -> -19 makes the total along d 8
  const BetaSample b = measure_beta(store_of(pts), down_spec());
  EXPECT_EQ(b.beta, b.beta_target);
  EXPECT_EQ(b.beta, 15.0 / 8.0);
}

TEST(Beta, EscapeSpeedLeavesSlowEjectaOut) {
  BetaSpec s = down_spec();
  s.escape_speed = 3.0;  // |v| of the first ejecta point is sqrt(10) > 3, the second's sqrt(5)
  const BetaSample b = measure_beta(store_of(after_impact()), s);
  EXPECT_EQ(b.ejecta_mass, 1.0);
  EXPECT_EQ(b.beta, 1.0 + 1.0 / 8.0);
}

TEST(Beta, ObliqueDirectionProjectsOnTheImpactVelocity) {
  // Impactor moving along d = (0.6, 0, -0.8) at 5 m/s (exact in binary up to the last bit, so
  // compared to 1e-15); one ejecta point moving straight up at 2 m/s: p_ej . (-d) = 1 x 2 x 0.8.
  BetaSpec s = down_spec();
  s.direction = Eigen::Vector3d(0.6, 0.0, -0.8);
  s.impact_speed = 5.0;
  using V = Eigen::Vector3d;
  const std::vector<P> pts = {{V(0, 0, -1), V::Zero(), 2.0, 1}, {V(0, 0, 1), V(0, 0, 2), 1.0, 0}};
  const BetaSample b = measure_beta(store_of(pts), s);
  EXPECT_NEAR(b.beta, 1.0 + 1.6 / 10.0, 1e-15);
}

TEST(Beta, ImpactorMassBeforeTheImpactSetsPimp) {
  // An impactor point that has left the domain must not change p_imp: beta_sample takes the
  // mass of the first sample. Here the buried impactor lost half its points (1 of 2 kg).
  auto pts = after_impact();
  pts[0].m = 1.0;
  auto s = beta_sums(store_of(pts), down_spec());
  const BetaSample b = beta_sample(s, down_spec(), 2.0);
  EXPECT_EQ(b.impactor_momentum, 8.0);
  EXPECT_EQ(b.beta, 1.0 + 7.0 / 8.0);
}

TEST(Beta, SameBitsInAnyParticleOrder) {
  // Random non-integer values: the exact sums make the result independent of the order.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  std::vector<P> pts;
  for (int i = 0; i < 500; ++i) {
    pts.push_back({Eigen::Vector3d(u(rng), u(rng), u(rng)), Eigen::Vector3d(u(rng), u(rng), u(rng)),
                   1.0 + 0.1 * u(rng), i % 7 == 0});
  }
  const BetaSample a = measure_beta(store_of(pts), down_spec());
  std::vector<std::uint32_t> order(pts.size());
  std::iota(order.begin(), order.end(), 0U);
  std::shuffle(order.begin(), order.end(), rng);
  ParticleStore s = store_of(pts);
  s.permute(order);
  const BetaSample b = measure_beta(s, down_spec());
  EXPECT_EQ(a.beta, b.beta);
  EXPECT_EQ(a.beta_target, b.beta_target);
  EXPECT_EQ(a.ejecta_mass, b.ejecta_mass);
}

TEST(EjectaLaunches, FirstCrossingIsRecordedOnceAndSortedBySpeed) {
  const BetaSpec spec = down_spec();
  auto pts = after_impact();
  EjectaLaunches l;
  l.set_impactor(2.0, 4.0);
  l.record(store_of(pts), spec, 1.0);
  ASSERT_EQ(l.size(), 2U);
  EXPECT_EQ(l.launches().at(1).radius, 1.0);  // (1, 0) from the axis through the origin
  EXPECT_EQ(l.launches().at(1).height, 2.0);
  // Counted at launch: the two ejecta carry 1 + 6 kg m/s against d, over m U = 2 x 4.
  EXPECT_EQ(l.beta_at_launch(0.0), 1.0 + 7.0 / 8.0);
  EXPECT_EQ(l.beta_at_launch(3.0), 1.0 + 1.0 / 8.0);  // |v| = sqrt(5) < 3 is left out
  // |v| = sqrt(5): one rounding in the square root and one in the square, 1e-15 covers both.
  EXPECT_NEAR(l.launches().at(2).speed * l.launches().at(2).speed, 5.0, 1e-15 * 5.0);
  // Later the falling point turns outward and the first ejecta speed up: only the new one is
  // added, the others keep their launch values.
  pts[3].v.z() = 1.0;
  pts[1].v *= 10.0;
  l.record(store_of(pts), spec, 2.0);
  ASSERT_EQ(l.size(), 3U);
  EXPECT_EQ(l.launches().at(1).time, 1.0);
  EXPECT_EQ(l.launches().at(3).time, 2.0);
  const std::string text = l.csv();
  // Fastest first: sqrt(10) (1 kg), sqrt(5) (3 kg), 1 (1 kg): cumulative 1, 4, 5 kg.
  EXPECT_NE(text.find(",1\n"), std::string::npos);
  EXPECT_NE(text.find(",4\n"), std::string::npos);
  EXPECT_NE(text.find(",5\n"), std::string::npos);
  EXPECT_LT(text.find("\n1,1,"), text.find("\n2,1,"));
  // Read back up to t = 1.5 (a resume from a checkpoint there): the launch at t = 2 goes.
  EjectaLaunches r;
  r.read(text, "test", 1.5);
  EXPECT_EQ(r.size(), 2U);
  EXPECT_EQ(r.launches().at(2).mass, 3.0);
  EXPECT_EQ(r.impactor_mass(), 2.0);  // from the table's first line
  r.record(store_of(pts), spec, 2.0);
  EXPECT_EQ(r.csv(), text);  // the resumed record writes the same table
  EXPECT_THROW(r.read("nonsense\n", "bad.csv", 1.0), std::runtime_error);
}

}  // namespace
}  // namespace shatter
