#include "shatter/scene/build.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <set>

#include "scene_fixture.hpp"

namespace shatter::scene {
namespace {

TEST(SceneBuild, OneGroupPerBodyWithConsistentColumns) {
  const Scene s = test::parse(test::kTinyScene);
  const BuiltScene setup = build(s);
  const ParticleStore& P = setup.particles;
  ASSERT_EQ(P.groups().size(), 2u);
  ASSERT_EQ(setup.materials.size(), 2u);
  EXPECT_EQ(setup.damaged, (std::vector<bool>{false, true}));
  EXPECT_EQ(P.size(), s.particle_count());

  std::set<std::int64_t> ids;
  for (std::size_t g = 0; g < 2; ++g) {
    const Range r = P.groups()[g].range;
    EXPECT_EQ(P.groups()[g].material, static_cast<int>(g));
    EXPECT_EQ(r.size(), s.bodies[g].fill.points.size());
    double mass = 0.0;
    for (std::size_t p = r.begin; p < r.end; ++p) {
      EXPECT_EQ(P.col(IField::body)[p], static_cast<std::int64_t>(g));
      EXPECT_EQ(P.col(Field::size0)[p], s.bodies[g].spacing);
      EXPECT_DOUBLE_EQ(P.col(Field::mass)[p], P.col(Field::rho)[p] * P.col(Field::volume0)[p]);
      EXPECT_EQ(P.col(Field::vx)[p], s.bodies[g].velocity.x());
      EXPECT_GT(P.col(Field::z)[p], 0.0);  // half model
      ids.insert(P.col(IField::id)[p]);
      mass += P.col(Field::mass)[p];
    }
    // The half body has half the true mass (rho0 times half the sphere volume), to the 0.2 %
    // of the volume measure at this coarse resolution.
    const double radius = std::get<Sphere>(s.bodies[g].shape.parts[0]).radius;
    const double exact = 0.5 * setup.materials[g]->reference_density() * 4.0 / 3.0 *
                         std::numbers::pi * std::pow(radius, 3);
    EXPECT_NEAR(mass / exact, 1.0, 2e-3) << s.bodies[g].name;
  }
  EXPECT_EQ(ids.size(), P.size());  // ids unique
}

TEST(SceneBuild, TargetCarriesInitialisedFlaws) {
  const BuiltScene setup = build(test::parse(test::kTinyScene));
  const ParticleStore& P = setup.particles;
  ASSERT_TRUE(P.has(Field::eps_min));
  ASSERT_TRUE(P.has(Field::n_flaws));
  const Range target = P.groups()[1].range;
  for (std::size_t p = target.begin; p < target.end; ++p) {
    EXPECT_GT(P.col(Field::eps_min)[p], 0.0);
    EXPECT_GE(P.col(Field::eps_max)[p], P.col(Field::eps_min)[p]);
    EXPECT_GE(P.col(Field::n_flaws)[p], 1.0);
  }
}

TEST(SceneBuild, FlawsDependOnTheSeed) {
  const BuiltScene a = build(test::parse(test::kTinyScene));
  const BuiltScene b = build(test::parse(test::kTinyScene, {"fracture.seed=2"}));
  const BuiltScene c = build(test::parse(test::kTinyScene));
  const auto ea = a.particles.col(Field::eps_min);
  const auto eb = b.particles.col(Field::eps_min);
  const auto ec = c.particles.col(Field::eps_min);
  EXPECT_TRUE(std::equal(ea.begin(), ea.end(), ec.begin()));
  EXPECT_FALSE(std::equal(ea.begin(), ea.end(), eb.begin()));
}

}  // namespace
}  // namespace shatter::scene
