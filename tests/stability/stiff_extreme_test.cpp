// Stiff and extreme cases (issue 5, "Stiff and extreme cases"; DESIGN.md "stability"): coarse
// versions of scenes/stability/*.toml run in-process through the same path as `shatter run`
// (load_scene with --set overrides, build, Simulation), one thread, so every step can be
// inspected. Each test checks that the run reaches its end time without a NumericalError (the
// engine's NaN and dt_min checks) or a non-finite field, that the energy error stays inside a
// stated bound, that the time step does not collapse, and the one property that makes its scene
// worth running (otherwise a quiet run would prove nothing): the 15 km/s impact really enters
// the Tillotson expanded and vapour branches, the stiff target really has the stiff wave speed,
// the grazing and few-point projectiles really hit, the far flyer really leaves a sparse grid.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "eos/tillotson.hpp"
#include "shatter/grid/sparse_grid.hpp"
#include "shatter/mpm/simulation.hpp"
#include "shatter/scene/build.hpp"
#include "shatter/scene/scene.hpp"

namespace {

using shatter::Field;
using shatter::Simulation;
using shatter::eos::TillotsonRegion;

constexpr std::size_t kRegions = 5;

// What one run did, step by step.
struct Record {
  std::string error;  // NumericalError message; empty when the run reached its end time
  double end_time = 0.0;
  int symmetry_axis = -1;
  double time = 0.0;
  std::uint64_t steps = 0;
  double dt_first = 0.0;  // stable dt of the initial state (Eq. 34)
  double dt_min = std::numeric_limits<double>::infinity();
  double dt_max = 0.0;
  // max over steps of (dt taken) / (stable dt of the state it left): the step's effective CFL
  // divided by the configured one.
  double worst_step_ratio = 0.0;
  std::uint64_t retakes = 0;        // steps the engine took again (Simulation::retakes)
  double worst_energy_error = 0.0;  // max over steps of |EnergyBudget::error()|
  double final_energy_error = 0.0;
  double max_pressure = 0.0;  // Pa, over all points and steps
  double max_energy = 0.0;    // J/kg, specific internal energy (the temperature-like measure)
  std::size_t blocks_first = 0, blocks_max = 0;  // grid blocks after the first step, and most
  std::size_t grid_bytes_first = 0, grid_bytes_max = 0;
  double bbox_blocks_last = 0.0;  // blocks of the particles' bounding box at the end
  // Per body: the most points found at once in each Tillotson region (empty for other EOS).
  std::vector<std::array<std::size_t, kRegions>> regions;
  std::vector<std::string> bodies;  // names, in body (= group) order
  std::vector<std::size_t> points;  // per body, at the start
  double seconds = 0.0;             // wall time of the run
};

std::string scene_file(const std::string& name) {
  return std::string(SHATTER_SOURCE_DIR) + "/scenes/stability/" + name + ".toml";
}

// Tillotson parameters of a body's material, or none.
std::optional<shatter::eos::Tillotson> tillotson_of(const shatter::scene::BodySpec& b) {
  if (b.material.eos != "tillotson") return std::nullopt;
  const auto& m = b.material;
  shatter::eos::TillotsonParams q;
  q.rho0 = m.get("rho0");
  q.A = m.get("A");
  q.B = m.get("B");
  q.a = m.get("a");
  q.b = m.get("b");
  q.E0 = m.get("E0");
  q.Eiv = m.get("Eiv");
  q.Ecv = m.get("Ecv");
  q.rho_iv = m.params.count("rho_iv") ? m.get("rho_iv") : 0.0;
  q.alpha = m.get("alpha");
  q.beta = m.get("beta");
  return shatter::eos::Tillotson(q);
}

void sample(const Simulation& sim, const shatter::scene::Scene& scene, Record& r) {
  const auto& P = sim.particles();
  const auto p = P.col(Field::pressure), e = P.col(Field::energy), rho = P.col(Field::rho);
  for (std::size_t k = 0; k < P.size(); ++k) {
    r.max_pressure = std::max(r.max_pressure, p[k]);
    r.max_energy = std::max(r.max_energy, e[k]);
  }
  for (const auto& g : P.groups()) {
    const auto body = static_cast<std::size_t>(g.material);  // group g is body g (build.hpp)
    const auto eos = tillotson_of(scene.bodies[body]);
    if (!eos) continue;
    std::array<std::size_t, kRegions> n{};
    for (std::size_t k = g.range.begin; k < g.range.end; ++k)
      ++n[static_cast<std::size_t>(eos->region(rho[k], e[k]))];
    for (std::size_t i = 0; i < kRegions; ++i)
      r.regions[body][i] = std::max(r.regions[body][i], n[i]);
  }
  r.blocks_max = std::max(r.blocks_max, sim.active_blocks());
  r.grid_bytes_max = std::max(r.grid_bytes_max, sim.grid_bytes());
}

double bounding_box_blocks(const Simulation& sim) {
  const auto& P = sim.particles();
  const double block = shatter::SparseGrid::kBlock * sim.config().cell_size;
  double n = 1.0;
  for (const Field f : {Field::x, Field::y, Field::z}) {
    const auto c = P.col(f);
    const auto [lo, hi] = std::minmax_element(c.begin(), c.end());
    n *= std::floor(*hi / block) - std::floor(*lo / block) + 1.0;
  }
  return n;
}

// Every column the engine and the models evolve must be finite at the end (the engine checks a
// subset every step; pressure and energy are checked here too).
std::string first_non_finite(const Simulation& sim) {
  const auto& P = sim.particles();
  for (const Field f : {Field::x, Field::y, Field::z, Field::vx, Field::vy, Field::vz, Field::rho,
                        Field::energy, Field::pressure, Field::soundspeed, Field::sxx, Field::syy,
                        Field::szz, Field::sxy, Field::syz, Field::sxz}) {
    const auto c = P.col(f);
    for (std::size_t k = 0; k < c.size(); ++k)
      if (!std::isfinite(c[k]))
        return std::string(shatter::name_of(f)) + " of point " + std::to_string(k);
  }
  return {};
}

std::size_t body_index(const Record& r, const std::string& name) {
  const auto it = std::find(r.bodies.begin(), r.bodies.end(), name);
  EXPECT_NE(it, r.bodies.end()) << "no body " << name;
  return static_cast<std::size_t>(it - r.bodies.begin());
}

// Runs a scene as `shatter run` does (steps land exactly on the end time), sampling every step.
Record run(const std::string& name, const std::vector<std::string>& sets,
           const std::function<void(const Simulation&, const Record&)>& after = {}) {
  const auto t0 = std::chrono::steady_clock::now();
  const auto scene = shatter::scene::load_scene(scene_file(name), sets);
  auto built = shatter::scene::build(scene);
  Record r;
  r.end_time = scene.end_time;
  r.symmetry_axis = scene.symmetry_axis;
  r.regions.resize(scene.bodies.size());
  for (const auto& b : scene.bodies) {
    r.bodies.push_back(b.name);
    r.points.push_back(b.fill.points.size());
  }
  Simulation sim(scene.solver, std::move(built.particles), built.materials, 1);
  r.dt_first = sim.clock().dt;
  try {
    while (sim.time() < scene.end_time) {
      const double t_before = sim.time();
      if (sim.time() + sim.clock().dt >= scene.end_time) {
        sim.advance_to(scene.end_time);
      } else {
        sim.step();
      }
      // clock().dt is the next stable step (Eq. 34), never the one shortened to land on the end.
      if (r.blocks_first == 0) {  // the grid is built by the first step
        r.blocks_first = sim.active_blocks();
        r.grid_bytes_first = sim.grid_bytes();
      }
      r.dt_min = std::min(r.dt_min, sim.clock().dt);
      r.dt_max = std::max(r.dt_max, sim.clock().dt);
      r.worst_step_ratio = std::max(r.worst_step_ratio, (sim.time() - t_before) / sim.clock().dt);
      r.worst_energy_error = std::max(r.worst_energy_error, std::abs(sim.energy().error()));
      sample(sim, scene, r);
    }
  } catch (const shatter::NumericalError& e) {
    r.error = e.what();
  }
  r.time = sim.time();
  r.steps = sim.clock().step;
  r.retakes = sim.retakes();
  r.final_energy_error = sim.energy().error();
  r.bbox_blocks_last = bounding_box_blocks(sim);
  if (r.error.empty()) {
    const auto bad = first_non_finite(sim);
    if (!bad.empty()) r.error = "non-finite " + bad;
  }
  if (after) after(sim, r);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf(
      "[ %s ] %llu steps (%llu retaken) to t = %.3g s, dt %.3g .. %.3g s (first %.3g, min/first "
      "%.3f), largest dt taken / next stable dt %.3f, energy error max %.3e final %.3e, p_max "
      "%.3g Pa, E_max %.3g J/kg, blocks %zu .. %zu (box %.0f), %.1f s wall\n",
      name.c_str(), static_cast<unsigned long long>(r.steps),
      static_cast<unsigned long long>(r.retakes), r.time, r.dt_min, r.dt_max, r.dt_first,
      r.dt_min / r.dt_first, r.worst_step_ratio, r.worst_energy_error, r.final_energy_error,
      r.max_pressure, r.max_energy, r.blocks_first, r.blocks_max, r.bbox_blocks_last, r.seconds);
  for (std::size_t b = 0; b < r.regions.size(); ++b) {
    std::printf("  %s: most points at once per Tillotson region:", r.bodies[b].c_str());
    for (std::size_t i = 0; i < kRegions; ++i)
      std::printf(" %s %zu", shatter::eos::name_of(static_cast<TillotsonRegion>(i)),
                  r.regions[b][i]);
    std::printf("\n");
  }
  return r;
}

// The checks every scene shares. `energy_tolerance` is the scene's bound on |energy error|;
// `dt_floor` the smallest allowed ratio min dt / first dt.
void expect_stable(const Record& r, double energy_tolerance, double dt_floor) {
  EXPECT_TRUE(r.error.empty()) << r.error;
  EXPECT_EQ(r.time, r.end_time) << "the run stopped before its end time";
  EXPECT_LT(r.worst_energy_error, energy_tolerance);
  EXPECT_GT(r.dt_min / r.dt_first, dt_floor) << "time step collapsed: " << r.dt_min << " s";
}

// Momentum |sum m v| of body `b` (group b) in the plane of the motion: the component normal to
// a symmetry plane is left out, as the mirror half that would cancel it is not simulated.
double body_momentum(const Simulation& sim, std::size_t b, int symmetry_axis) {
  const auto& P = sim.particles();
  const auto m = P.col(Field::mass);
  const std::array<std::span<const double>, 3> v = {P.col(Field::vx), P.col(Field::vy),
                                                    P.col(Field::vz)};
  std::array<double, 3> p{};
  for (const auto& g : P.groups()) {
    if (static_cast<std::size_t>(g.material) != b) continue;
    for (std::size_t k = g.range.begin; k < g.range.end; ++k)
      for (int a = 0; a < 3; ++a) p[a] += m[k] * v[a][k];
  }
  if (symmetry_axis >= 0) p[static_cast<std::size_t>(symmetry_axis)] = 0.0;
  return std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
}

// The CI grid: 4 mm cells (2 mm target spacing), about 4 000 target points in the half model,
// the coarsest at which the 7 mm projectile still has points (except where a scene sets its own).
const std::string kCoarse = "solver.cell_size=4.0e-3";

std::size_t in_region(const Record& r, const std::string& body, TillotsonRegion region) {
  return r.regions[body_index(r, body)][static_cast<std::size_t>(region)];
}

}  // namespace

namespace {

// 15 km/s head-on: the shocked states must leave the reference branch of the Tillotson EOS.
// Checked against the same scene at the laboratory 3.2 km/s, where the target stays below
// incipient vaporisation: so the region count measures the impact speed, not a mislabelling.
TEST(HypervelocityImpact, FifteenKmPerSecondReachesTillotsonVapourRegionsStably) {
  const Record r = run("hypervelocity-15kms", {kCoarse, "solver.end_time=6.0e-6"});
  // Energy: the paper keeps the error below 0.6 % at 3.2 km/s and 0.8 mm spacing. Here the shock
  // is ~20 times stronger in energy, the projectile only ~2 cells across, and most of the energy
  // goes through the artificial viscosity within a few steps of contact. The coarse run measured
  // 2.5 % while the contact step ran at an effective CFL of 1.37, and measures 0.39 % since that
  // step is retaken; 1 % flags the contact error coming back (an energy blow-up grows without
  // bound).
  // dt: after contact max(c + |v|) is set by the shocked nylon and the viscosity's signal speed
  // (~4x the 15 km/s of the first step in the coarse run); a factor 20 would be a collapse.
  expect_stable(r, 0.01, 0.05);
  // First contact: the signal speed jumps ~4x within the contact step. Without step control that
  // step ran at an effective CFL of cfl x 4.3 = 1.3 and made the +1.8 % energy error by itself
  // (docs/stability.md, observation 2); the engine now takes such a step again, so no accepted
  // step exceeds retake_ratio (2) times the stable step of the state it leaves.
  EXPECT_GT(r.retakes, 0u) << "contact did not trigger step control";
  EXPECT_LE(r.worst_step_ratio, 2.0);
  // The nylon (Ecv = 2.4 MJ/kg) is shocked far past complete vaporisation and releases into the
  // hot expanded branch (Eq. 9). The basalt under it takes ~10 MJ/kg, between incipient (4.72)
  // and complete (18.2 MJ/kg) vaporisation, and expands into the mixing branch (Eq. 10).
  EXPECT_GT(in_region(r, "projectile", TillotsonRegion::hot_expanded), 0u);
  const auto target_hot = [](const Record& x) {
    return in_region(x, "target", TillotsonRegion::mixed) +
           in_region(x, "target", TillotsonRegion::hot_expanded);
  };
  EXPECT_GT(target_hot(r), 0u);
  EXPECT_GT(r.max_energy, 18.2e6);

  const Record lab =
      run("hypervelocity-15kms", {kCoarse, "solver.end_time=6.0e-6", "impact.speed=3200"});
  EXPECT_TRUE(lab.error.empty()) << lab.error;
  EXPECT_EQ(target_hot(lab), 0u);
}

// 80 degrees from the normal: the projectile skims the target. It must touch it (the target
// takes up momentum) and run to the end with the error bound of the laboratory smoke test.
TEST(GrazingImpact, EightyDegreesRunsToEndAndTransfersMomentum) {
  double target_momentum = 0.0, projectile_momentum = 0.0;
  const Record r = run(
      "grazing-80deg", {kCoarse, "solver.end_time=20.0e-6"},
      [&](const Simulation& sim, const Record& rec) {
        target_momentum = body_momentum(sim, body_index(rec, "target"), rec.symmetry_axis);
        projectile_momentum = body_momentum(sim, body_index(rec, "projectile"), rec.symmetry_axis);
      });
  // 2 %: the bound of tests/validation/lab_impact_smoke.cpp for the same grid and speed.
  expect_stable(r, 0.02, 0.1);
  // The sliver contact passes a few per cent of the projectile's momentum to the target (the
  // normal component is cos 80 = 17 % of it); zero would mean the bodies never met.
  const double share = target_momentum / (target_momentum + projectile_momentum);
  std::printf("  target's share of the momentum: %.3f\n", share);
  EXPECT_GT(share, 0.01);
}

// E = 1000 GPa: dt must follow the stiff longitudinal wave speed from the first step (a dt from
// the EOS sound speed alone would be ~3 times too long and blow up), and stay stable.
TEST(StiffTarget, ThousandGigapascalTargetUsesStiffWaveSpeedAndStaysStable) {
  const auto scene = shatter::scene::load_scene(scene_file("stiff-target"), {kCoarse});
  const auto& target = *std::find_if(scene.bodies.begin(), scene.bodies.end(),
                                     [](const auto& b) { return b.name == "target"; });
  const double E = target.material.get("young"), nu = target.material.get("poisson");
  ASSERT_EQ(E, 1000.0e9);
  const double G = E / (2.0 * (1.0 + nu)), K = target.material.get("A");
  const double c_p = std::sqrt((K + 4.0 / 3.0 * G) / target.material.get("rho0"));

  const Record r = run("stiff-target", {kCoarse, "solver.end_time=10.0e-6"});
  // First step of Eq. 34: the target's c_p (~19.8 km/s) exceeds the projectile's c + |v|.
  EXPECT_NEAR(r.dt_first, scene.solver.cfl * scene.solver.cell_size / c_p, 1e-3 * r.dt_first);
  // 2 %: as the laboratory smoke test; the stiff wall reflects the projectile's energy instead
  // of absorbing it, so an unstable stress update would show as growth here.
  expect_stable(r, 0.02, 0.2);
}

// A projectile of a few points (spacing larger than a cell) must still hit, and neither its
// few points nor the target under them may run away.
TEST(FewPointProjectile, TwoPointsAcrossStillHitsWithoutBlowUp) {
  double target_momentum = 0.0;
  // The scene's 3 mm projectile spacing is kept: 2.3 points across. On the 4 mm CI grid the
  // points are no longer larger than a cell; the full scene (2.4 mm cells) tests that too.
  const Record r = run("few-point-projectile", {kCoarse, "solver.end_time=15.0e-6"},
                       [&](const Simulation& sim, const Record& rec) {
                         target_momentum =
                             body_momentum(sim, body_index(rec, "target"), rec.symmetry_axis);
                       });
  const std::size_t n = r.points[body_index(r, "projectile")];
  EXPECT_GE(n, 1u);
  EXPECT_LE(n, 8u) << "the projectile is meant to be a few points (half model)";
  expect_stable(r, 0.02, 0.1);
  // Projectile momentum 0.2 g x 3.2 km/s (half model: 0.33 kg m/s); the target must take a
  // good part of it.
  std::printf("  target momentum: %.3f kg m/s\n", target_momentum);
  EXPECT_GT(target_momentum, 0.05);
}

// A fragment leaves at 6.2 km/s on an open grid. The grid must follow it with about the same
// number of blocks, while the particles' bounding box grows to thousands of blocks; free flight
// must conserve energy to round-off and keep dt constant.
TEST(FarFlyer, GridGrowsWithOccupiedBlocksNotBoundingBox) {
  const Record r = run("far-flyer", {kCoarse, "solver.end_time=100.0e-6"});
  // Nothing deforms, so the energy error is round-off (measured ~2e-15).
  expect_stable(r, 1e-12, 0.9);
  // The fragment crosses block boundaries, so its footprint varies by a layer of blocks; a dense
  // grid over the bounding box would be ~100 times more.
  EXPECT_LE(r.blocks_max, 2 * r.blocks_first);
  EXPECT_LE(r.grid_bytes_max, 2 * r.grid_bytes_first);
  EXPECT_GT(r.bbox_blocks_last, 50.0 * static_cast<double>(r.blocks_max))
      << "the fragment did not get far enough for the test to mean anything";
}

}  // namespace
