// The laboratory impact's crater shock in one dimension (issue 27;
// scenes/diagnostics/planar-nylon-basalt.toml): a nylon slab hits basalt at 3.2 km/s in uniaxial
// strain. Behind the shock every basalt point should sit on one state, the impedance match of the
// two materials' principal Hugoniots. MPM's default (FLIP, 2 points per cell per axis) leaves the
// points scattered around it by a third of the pressure; XPIC (Hammerquist & Nairn 2017) with its
// removed kinetic energy booked as heat (DeBar 1974) and one point per cell per axis holds them
// three times closer. The test pins both: the plateau of the shock configuration against the
// jump conditions, and its scatter against the default's, measured in the same run of the test.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <unordered_map>
#include <vector>

#include "shatter/material/probe.hpp"
#include "shatter/mpm/simulation.hpp"
#include "shatter/scene/build.hpp"
#include "shatter/scene/scene.hpp"

namespace shatter {
namespace {

constexpr double kImpactSpeed = 3200.0;  // m/s, the scene's flyer
constexpr double kSampleTime = 2.0e-6;   // s: before the release from the flyer's rear face

// The shocked state by impedance match: the particle speed up in the basalt at which its
// Hugoniot pressure equals nylon's at kImpactSpeed - up (both principal Hugoniots from the
// material probe, i.e. the Rankine-Hugoniot jump conditions with each material's own EOS).
HugoniotRow impedance_match(const MaterialSpec& target, const MaterialSpec& flyer) {
  auto p_of = [](const MaterialSpec& m, double up) {
    const double u[] = {up};
    return hugoniot(m, u).front();
  };
  double lo = 1.0, hi = kImpactSpeed - 1.0;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (p_of(target, mid).p > p_of(flyer, kImpactSpeed - mid).p ? hi : lo) = mid;
  }
  return p_of(target, 0.5 * (lo + hi));
}

struct Scatter {
  double mean_p = 0.0;  // Pa
  double std_p = 0.0;   // Pa, point to point
  double mean_e = 0.0;  // J/kg
  double std_e = 0.0;   // J/kg
  int n = 0;
};

// Pressure and energy of the basalt points that started within 6 mm of the impact face (five
// point layers at 1.2 mm: all shocked, none released by kSampleTime).
Scatter shocked_points(const std::vector<std::string>& sets, HugoniotRow* expected) {
  const auto file = std::filesystem::path(SHATTER_SOURCE_DIR) / "scenes" / "diagnostics" /
                    "planar-nylon-basalt.toml";
  const auto scene = scene::load_scene(file, sets);
  if (expected) *expected = impedance_match(scene.bodies[1].material, scene.bodies[0].material);
  auto built = scene::build(scene);
  std::unordered_map<std::int64_t, double> x0;
  const ParticleStore& P0 = built.particles;
  for (std::size_t p = 0; p < P0.size(); ++p) {
    x0[P0.col(IField::id)[p]] = P0.col(Field::x)[p];
  }
  Simulation sim(scene.solver, std::move(built.particles), built.materials, 1);
  sim.advance_to(kSampleTime);
  const ParticleStore& P = sim.particles();
  Scatter s;
  double sp = 0, sp2 = 0, se = 0, se2 = 0;
  for (std::size_t p = 0; p < P.size(); ++p) {
    const double x = x0.at(P.col(IField::id)[p]);
    if (P.col(IField::body)[p] != 1 || x <= 0.0 || x >= 6e-3) continue;
    const double pr = P.col(Field::pressure)[p], e = P.col(Field::energy)[p];
    sp += pr, sp2 += pr * pr, se += e, se2 += e * e, ++s.n;
  }
  s.mean_p = sp / s.n;
  s.std_p = std::sqrt(std::max(sp2 / s.n - s.mean_p * s.mean_p, 0.0));
  s.mean_e = se / s.n;
  s.std_e = std::sqrt(std::max(se2 / s.n - s.mean_e * s.mean_e, 0.0));
  return s;
}

TEST(CraterShockPlateau, XpicWithHeatAndOnePointPerCellHoldsTheHugoniotState) {
  HugoniotRow hug;
  const std::vector<std::string> shock = {"solver.transfer=\"xpic\"", "solver.filter_heat=true",
                                          "solver.cell_size=1.2e-3", "body.flyer.points_per_cell=1",
                                          "body.slab.points_per_cell=1"};
  const Scatter fix = shocked_points(shock, &hug);
  const Scatter flip = shocked_points({}, nullptr);
  std::printf(
      "impedance match: up %.0f m/s, p %.2f GPa, E %.3f MJ/kg\n"
      "xpic + heat, 1 point per cell: p %.2f +- %.2f GPa, E %.3f +- %.3f MJ/kg (%d points)\n"
      "flip, 2 points per cell:       p %.2f +- %.2f GPa, E %.3f +- %.3f MJ/kg (%d points)\n",
      hug.up, hug.p * 1e-9, hug.energy * 1e-6, fix.mean_p * 1e-9, fix.std_p * 1e-9,
      fix.mean_e * 1e-6, fix.std_e * 1e-6, fix.n, flip.mean_p * 1e-9, flip.std_p * 1e-9,
      flip.mean_e * 1e-6, flip.std_e * 1e-6, flip.n);
  // The jump conditions give 16.6 GPa and 0.745 MJ/kg. Measured (main 2026-12): 14.9 +- 1.9 GPa,
  // 0.83 +- 0.17 MJ/kg; SPH on the same scene 14.5 GPa, 0.94 MJ/kg (docs/validation-lab-
  // impact.md). The mean sits ~10% low because the five layers still include the viscous
  // shock's tail (c_L = 0.06, c_Q = 2.25 over 1.2 mm cells): 20% bounds on the means.
  ASSERT_GT(fix.n, 100);
  EXPECT_NEAR(fix.mean_p, hug.p, 0.2 * hug.p);
  EXPECT_NEAR(fix.mean_e, hug.energy, 0.2 * hug.energy);
  // Point-to-point scatter: 12% of the Hugoniot pressure measured, 35% with the default; 18%
  // bound, and at most half the default's in the same test (the ingredient issue 27 isolates);
  // energy: 0.17 against 0.36 MJ/kg.
  EXPECT_LT(fix.std_p, 0.18 * hug.p);
  EXPECT_LT(fix.std_p, 0.5 * flip.std_p);
  EXPECT_LT(fix.std_e, 0.6 * flip.std_e);  // measured 0.46
}

}  // namespace
}  // namespace shatter
