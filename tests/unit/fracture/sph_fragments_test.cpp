// Fragments of SPH runs (issue 10 item 7; BA95 Sec. 4.4) through the shared fragment module:
// friends within one smoothing length, the one-layer damaged veneer, the scene keys that select
// them, and the catalogue of a short SPH impact.

#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "shatter/fracture/fragments.hpp"
#include "shatter/scene/build.hpp"
#include "shatter/scene/scene.hpp"
#include "shatter/sph/solver.hpp"
#include "support/sph_impact.hpp"

namespace shatter::sph {
namespace {

constexpr double kD = 1.0e-3;  // lattice spacing, m
constexpr double kMass = 1.0e-6;

struct Block {
  int nx, ny, nz;
  double x0;                             // x of the first plane
  double rho;                            // density (sets h = 1.2 (m / rho)^{1/3})
  int damaged_lo = -1, damaged_hi = -2;  // planes i in [lo, hi] have D = 1
};

// Lattice blocks with spacing kD (volume0 kD^3 each, so the spacing-based default link of the
// module is 1.5 kD).
ParticleStore make_store(const std::vector<Block>& blocks) {
  std::size_t n = 0;
  for (const Block& b : blocks) n += static_cast<std::size_t>(b.nx * b.ny * b.nz);
  ParticleStore s;
  s.require(FieldSet{Field::x, Field::y, Field::z, Field::vx, Field::vy, Field::vz, Field::mass,
                     Field::volume0, Field::rho, Field::damage});
  s.require(IField::id);
  s.require(IField::fragment);
  s.add_group(0, n);
  std::size_t p = 0;
  for (const Block& b : blocks) {
    for (int i = 0; i < b.nx; ++i) {
      for (int j = 0; j < b.ny; ++j) {
        for (int k = 0; k < b.nz; ++k, ++p) {
          s.col(Field::x)[p] = b.x0 + i * kD;
          s.col(Field::y)[p] = j * kD;
          s.col(Field::z)[p] = k * kD;
          s.col(Field::mass)[p] = kMass;
          s.col(Field::volume0)[p] = kD * kD * kD;
          s.col(Field::rho)[p] = b.rho;
          s.col(Field::damage)[p] = i >= b.damaged_lo && i <= b.damaged_hi ? 1.0 : 0.0;
          s.col(IField::id)[p] = static_cast<std::int64_t>(p);
        }
      }
    }
  }
  return s;
}

FragmentSearchSpec ba95(double factor = 1.2) {
  FragmentSearchSpec s;
  s.method = "friends_of_friends";
  s.smoothing_factor = factor;
  return s;
}

TEST(SphFragments, FriendsAreWithinOneSmoothingLength) {
  // Two 6x4x4 blocks whose facing planes are 1.3 kD apart. At rho = m / kD^3, h = 1.2 kD: not
  // friends (BA95), two fragments; the module's spacing-based link (1.5 kD) joins them.
  const double rho0 = kMass / (kD * kD * kD);
  ParticleStore s = make_store({{6, 4, 4, 0.0, rho0}, {6, 4, 4, 6.3 * kD, rho0}});
  const FragmentCatalogue apart = find_fragments(s, ba95());
  ASSERT_EQ(apart.fragments.size(), 2u);
  EXPECT_EQ(apart.fragments[0].particles, 96u);
  EXPECT_EQ(apart.fragments[1].particles, 96u);
  EXPECT_EQ(apart.dust_mass, 0.0);
  FragmentSearchSpec spacing;
  spacing.method = "friends_of_friends";
  EXPECT_EQ(find_fragments(s, spacing).fragments.size(), 1u);
  // The right block expanded to rho0 / 1.2^3: h = 1.44 kD there, and a pair across the gap
  // links at (h_i + h_j) / 2 = 1.32 kD > 1.3 kD: one fragment. (With either h alone, 1.2 or
  // 1.44 kD, the answer would differ from the pair mean's on one side.)
  ParticleStore t =
      make_store({{6, 4, 4, 0.0, rho0}, {6, 4, 4, 6.3 * kD, rho0 / (1.2 * 1.2 * 1.2)}});
  EXPECT_EQ(find_fragments(t, ba95()).fragments.size(), 1u);
  // A smaller factor cuts it again: h = 1.1 and 1.32 kD, mean 1.21 kD < 1.3 kD.
  EXPECT_EQ(find_fragments(t, ba95(1.1)).fragments.size(), 2u);
}

TEST(SphFragments, DamagedVeneerIsOneLayerThick) {
  // A 12x4x4 bar (h = 1.2 kD: friends are the 6 face neighbours, 1 kD; edge neighbours are
  // 1.41 kD). One damaged plane (i = 5) cuts it (BA95: damaged points do not link) and joins, as
  // the veneer, the fragment of its nearest undamaged friend (both sides 1 kD away; the tie goes
  // to the lower label): planes 0-5 and 6-11, 96 points each, no dust.
  const double rho0 = kMass / (kD * kD * kD);
  {
    ParticleStore s = make_store({{12, 4, 4, 0.0, rho0, 5, 5}});
    const FragmentCatalogue cat = find_fragments(s, ba95());
    ASSERT_EQ(cat.fragments.size(), 2u);
    EXPECT_EQ(cat.fragments[0].particles + cat.fragments[1].particles, 192u);
    EXPECT_EQ(cat.dust_mass, 0.0);
  }
  // Three damaged planes (i = 4, 5, 6): 4 joins the left part, 6 the right; 5 touches only
  // damaged points, whose neighbours the veneer rule does not search: dust. Left 4 + 1 planes
  // (80 points), right 5 + 1 planes (96), dust 16 points.
  {
    ParticleStore s = make_store({{12, 4, 4, 0.0, rho0, 4, 6}});
    const FragmentCatalogue cat = find_fragments(s, ba95());
    ASSERT_EQ(cat.fragments.size(), 2u);
    EXPECT_EQ(cat.fragments[0].particles, 96u);
    EXPECT_EQ(cat.fragments[1].particles, 80u);
    EXPECT_DOUBLE_EQ(cat.dust_mass, 16 * kMass);
  }
}

TEST(SphFragments, RefusesAStoreWithoutDensity) {
  ParticleStore s;
  s.require(FieldSet{Field::x, Field::y, Field::z, Field::vx, Field::vy, Field::vz, Field::mass,
                     Field::volume0, Field::damage});
  s.add_group(0, 2);
  for (std::size_t p = 0; p < 2; ++p) {
    s.col(Field::x)[p] = static_cast<double>(p) * kD;
    s.col(Field::mass)[p] = kMass;
    s.col(Field::volume0)[p] = kD * kD * kD;
  }
  try {
    find_fragments(s, ba95());
    FAIL() << "no rho column accepted";
  } catch (const std::logic_error& e) {
    EXPECT_NE(std::string(e.what()).find("rho"), std::string::npos) << e.what();
  }
}

// The shared small impact (tests/support/sph_impact.hpp) as a half model, with damage and
// BA95's fragment search.
const std::string kImpact = test::sph_impact_scene(
    {.solver = "symmetry_plane = \"z\"\n",
     .flaws = "total_flaws = 1.0e9\n",
     .tables = "[fracture]\nfragment_method = \"friends_of_friends\"\nstatic_strength = 10.0e6\n"});

TEST(SphFragments, SceneSelectsTheSmoothingLengthLinkAndACatalogueOfAnSphRunAddsUp) {
  const scene::Scene s = scene::parse_scene(kImpact, "impact.toml");
  EXPECT_EQ(s.fracture.search.smoothing_factor, s.sph.h_factor);
  EXPECT_EQ(s.fracture.search.static_strength, 10.0e6);
  // MPM keeps the module's spacing-based link; the pre-pass needs friends_of_friends.
  EXPECT_EQ(scene::parse_scene(kImpact, "impact.toml", {"solver.method=\"mpm\""})
                .fracture.search.smoothing_factor,
            0.0);
  EXPECT_THROW(
      scene::parse_scene(kImpact, "impact.toml", {"fracture.fragment_method=\"grid_density\""}),
      scene::SceneError);

  scene::BuiltScene b = scene::build(s);
  auto sim = scene::make_solver(s, std::move(b.particles), b.materials, 2);
  sim->advance_to(3.0e-6);  // the shock is in the target, damage has begun near the impact
  ParticleStore P = sim->particles();
  double mass = 0.0, damaged = 0.0;
  for (std::size_t p = 0; p < P.size(); ++p) {
    mass += P.col(Field::mass)[p];
    if (P.col(Field::damage)[p] >= s.fracture.search.damage_threshold) {
      damaged += P.col(Field::mass)[p];
    }
  }
  ASSERT_GT(damaged, 0.0);
  const FragmentCatalogue cat = find_fragments(P, s.fracture.search);
  ASSERT_FALSE(cat.fragments.empty());
  double in_fragments = 0.0;
  for (const Fragment& f : cat.fragments) in_fragments += f.mass;
  // Every point is in one fragment or in the dust (sums of ~500 masses: 1e-12 relative).
  EXPECT_NEAR(cat.total_mass, mass, 1e-12 * mass);
  EXPECT_NEAR(in_fragments + cat.dust_mass, mass, 1e-12 * mass);
  // The largest fragment is the bulk of the target: intact, far from the impact.
  EXPECT_GT(cat.fragments[0].mass, 0.5 * mass);
  std::printf(
      "SPH catalogue at 3 us: %zu fragments, largest %.3f of the mass, dust %.3f, failed "
      "%.3f\n",
      cat.fragments.size(), cat.fragments[0].mass / mass, cat.dust_mass / mass, damaged / mass);
}

}  // namespace
}  // namespace shatter::sph
