// BA99's bound remnant on hand-built catalogues (G = 1).

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "shatter/fracture/bound_remnant.hpp"

namespace shatter {
namespace {

Fragment frag(double m, Eigen::Vector3d r, Eigen::Vector3d v) {
  Fragment f;
  f.mass = m;
  f.centre = r;
  f.velocity = v;
  f.inertia = 0.4 * m * 0.01 * Eigen::Matrix3d::Identity();  // a sphere of radius 0.1
  return f;
}

FragmentCatalogue catalogue(std::vector<Fragment> f) {
  FragmentCatalogue c;
  for (std::size_t i = 0; i < f.size(); ++i) f[i].id = static_cast<std::int64_t>(i);
  c.fragments = std::move(f);
  for (const Fragment& x : c.fragments) c.total_mass += x.mass;
  return c;
}

// Escape speed from mass 1 at distance 1 is sqrt(2): 0.9 of it is bound, 1.1 is not.
TEST(BoundRemnant, BoundPairJoinsAndEscapingFragmentDoesNot) {
  const double ve = std::sqrt(2.0);
  const auto cat =
      catalogue({frag(1.0, {0, 0, 0}, {0, 0, 0}), frag(0.001, {1, 0, 0}, {0, 0.9 * ve, 0}),
                 frag(0.001, {-1, 0, 0}, {0, 1.1 * ve, 0})});
  const BoundRemnant r = bound_remnant(cat, 1.0);
  EXPECT_EQ(r.members, (std::vector<std::int64_t>{0, 1}));
  EXPECT_DOUBLE_EQ(r.mass, 1.001);
  // momentum of the pair over its mass
  EXPECT_NEAR(r.velocity.y(), 0.001 * 0.9 * ve / 1.001, 1e-15);
  // the pair's spin: L = m d x v about the centre of mass, along +z
  EXPECT_GT(r.omega.z(), 0.0);
  EXPECT_NEAR(r.angular_momentum.z(), 0.001 * 1.0 * 0.9 * ve / 1.001, 1e-12);
}

// A chain: C is bound to A + B but not to A alone, so it joins on the second pass.
TEST(BoundRemnant, ThreeBodyChainJoinsOnTheSecondPass) {
  // A (mass 1) at 0, B (mass 1) at x = 1 at rest: bound. C at x = 3 moving at 0.9: against A
  // alone the binding speed is sqrt(2/3) = 0.816 (unbound); against A + B (mass 2, centre 0.5)
  // it is sqrt(2 * 2 / 2.5) = 1.26 (bound).
  const auto cat = catalogue({frag(1.0, {0, 0, 0}, {0, 0, 0}), frag(1.0, {1, 0, 0}, {0, 0, 0}),
                              frag(0.01, {3, 0, 0}, {0, 0.9, 0})});
  const BoundRemnant r = bound_remnant(cat, 1.0);
  EXPECT_EQ(r.members, (std::vector<std::int64_t>{0, 1, 2}));
  EXPECT_EQ(r.iterations, 3);  // B joins, then C, then a pass where nothing joins
  EXPECT_NEAR(r.mass, 2.01, 1e-15);
}

// Everything flying apart: the remnant is the largest fragment alone, at its own speed.
TEST(BoundRemnant, DispersedFragmentsLeaveTheLargestAlone) {
  const auto cat = catalogue({frag(1.0, {0, 0, 0}, {2, 0, 0}), frag(0.5, {1, 0, 0}, {10, 0, 0}),
                              frag(0.5, {0, 1, 0}, {0, -10, 0})});
  const BoundRemnant r = bound_remnant(cat, 1.0);
  EXPECT_EQ(r.members, (std::vector<std::int64_t>{0}));
  EXPECT_DOUBLE_EQ(r.mass, 1.0);
  EXPECT_DOUBLE_EQ(r.speed(), 2.0);
  EXPECT_DOUBLE_EQ(r.spin(), 0.0);
}

TEST(BoundRemnant, EmptyCatalogueHasNoRemnant) {
  const BoundRemnant r = bound_remnant(FragmentCatalogue{}, 1.0);
  EXPECT_EQ(r.mass, 0.0);
  EXPECT_TRUE(r.members.empty());
}

}  // namespace
}  // namespace shatter

namespace shatter {
namespace {

TEST(BoundRemnant, JsonReportHoldsMassSpeedAndSpin) {
  FragmentCatalogue cat;
  Fragment f;
  f.mass = 2.0;
  f.velocity = {3.0, 4.0, 0.0};
  cat.fragments.push_back(f);
  cat.total_mass = 4.0;
  const BoundRemnant r = bound_remnant(cat, 1.0);
  const auto file = std::filesystem::temp_directory_path() / "shatter_bound_remnant_test.json";
  write_bound_remnant_json(r, cat, file);
  std::ifstream in(file);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::filesystem::remove(file);
  EXPECT_NE(text.find("\"mass_kg\": 2,"), std::string::npos) << text;
  EXPECT_NE(text.find("\"mass_fraction\": 0.5,"), std::string::npos) << text;
  EXPECT_NE(text.find("\"speed_m_per_s\": 5,"), std::string::npos) << text;
  EXPECT_NE(text.find("\"spin_rate_rad_per_s\": 0,"), std::string::npos) << text;
  EXPECT_NE(text.find("\"fragments\": [0]"), std::string::npos) << text;
}

}  // namespace
}  // namespace shatter
