// The engine's verification problems as scenes (scenes/verification/*.toml): every scene there
// must parse and build, and each is run in-process through the same path as `shatter run`
// (load_scene with --set overrides, build, Simulation, one thread) and checked against its
// analytic or reference answer, the number its header comment tells a user to compare. These
// are the user-facing copies of tests/verification{,/engine}: what they add is that the scene
// format, the catalogue materials and the scene's boundaries reproduce the engine tests' numbers.
// All run at the scenes' own resolution except the symmetry plane (coarsened with --set, the
// check is exact at any resolution); the bar cannot be coarsened (one body per point slab).
// Release: 3.3 s for the whole file (one thread); ASan + UBSan (RelWithDebInfo): 23 s.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <numbers>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "shatter/material/catalogue.hpp"
#include "shatter/material/probe.hpp"
#include "shatter/mpm/simulation.hpp"
#include "shatter/scene/build.hpp"
#include "shatter/scene/scene.hpp"

namespace {

namespace fs = std::filesystem;
using shatter::Field;
using shatter::IField;
using shatter::Simulation;

fs::path scene_dir() {
  return fs::path(SHATTER_SOURCE_DIR) / "scenes" / "verification";
}

shatter::scene::Scene load(const std::string& name, const std::vector<std::string>& sets = {}) {
  return shatter::scene::load_scene(scene_dir() / (name + ".toml"), sets);
}

std::unique_ptr<Simulation> start(const shatter::scene::Scene& scene) {
  auto built = shatter::scene::build(scene);
  return std::make_unique<Simulation>(scene.solver, std::move(built.particles), built.materials, 1);
}

// Steps to t as `shatter run` does (stable steps, the last one shortened to land on t), calling
// after() once per step.
void run_to(Simulation& sim, double t, const std::function<void()>& after = {}) {
  while (sim.time() < t) {
    if (sim.time() + sim.clock().dt >= t) {
      sim.advance_to(t);
    } else {
      sim.step();
    }
    if (after) after();
  }
}

// Mean of column f over the points whose x lies in (lo, hi), and how many there are.
std::pair<double, int> mean_in(const shatter::ParticleStore& P, Field f, double lo, double hi,
                               bool absolute = false) {
  double sum = 0.0;
  int n = 0;
  const auto x = P.col(Field::x), c = P.col(f);
  for (std::size_t p = 0; p < P.size(); ++p) {
    if (x[p] > lo && x[p] < hi) {
      sum += absolute ? std::abs(c[p]) : c[p];
      ++n;
    }
  }
  return {n > 0 ? sum / n : 0.0, n};
}

double total_mass(const shatter::ParticleStore& P) {
  double m = 0.0;
  for (const double v : P.col(Field::mass)) m += v;
  return m;
}

}  // namespace

// Every scene in the folder is read with its defaults and builds a non-empty particle set; the
// list guards against a scene silently disappearing.
TEST(VerificationScenes, EverySceneParsesAndBuilds) {
  std::set<std::string> found;
  for (const auto& entry : fs::directory_iterator(scene_dir())) {
    if (entry.path().extension() != ".toml" || entry.path().filename() == "materials.toml") {
      continue;
    }
    SCOPED_TRACE(entry.path().string());
    const auto scene = shatter::scene::load_scene(entry.path());
    const auto built = shatter::scene::build(scene);
    EXPECT_GT(built.particles.size(), 0u);
    EXPECT_GT(scene.end_time, 0.0);
    found.insert(entry.path().stem().string());
  }
  for (const char* name :
       {"vibrating-bar", "wave-speed", "colliding-spheres", "symmetry-plane-full",
        "symmetry-plane-half", "sod-shock-tube", "planar-impact-aluminium", "noh-planar"}) {
    EXPECT_TRUE(found.count(name)) << name << ".toml is missing";
  }
}

// Problem 1: mode-1 vibrating bar, 32 cells, 5.125 periods. The centre-of-mass velocity is
// 0.06366 cos(omega t), omega = 0.6283 rad/s (T = 10 s). Bounds as the engine test's at 32 cells
// with uGIMP (max 4e-2, RMS 2e-2; grid dispersion ~(beta h)^2 accumulating over 10 pi rad);
// measured 1.56e-2 and 7.5e-3, the engine test's own numbers, so the 64-body scene is the engine
// problem. The period from the ten zero crossings: measured 10.004 s; 0.5 % rejects a wrong
// modulus or density (a 1 % error in E moves T by 0.5 %). Energy: kinetic + internal is
// compared with its start (measured drift 6.6e-5). EnergyBudget::error() agrees since e1d4e27
// (before, it booked ~0.5 % per period of "boundary work" at the clamped end; the engine test
// VibratingBarAt32Cells.ClampedEndDoesNoWork guards that).
TEST(VerificationScenes, VibratingBarPeriodAndCentreOfMassVelocity) {
  const auto scene = load("vibrating-bar");
  auto sim = start(scene);
  const double mass = total_mass(sim->particles());
  EXPECT_NEAR(mass, 15.2587890625, 1e-9);  // rho L h^2: the slab bodies fill the bar exactly
  const double omega = std::numbers::pi / 5.0, amplitude = 0.1 * 2.0 / std::numbers::pi;
  const double e0 = sim->energy().kinetic + sim->energy().internal;
  double max_err = 0.0, sum_sq = 0.0, worst_drift = 0.0, previous_v = 0.0, previous_t = 0.0;
  int samples = 0;
  std::vector<double> crossings;
  run_to(*sim, scene.end_time, [&] {
    const auto& P = sim->particles();
    double mv = 0.0;
    for (std::size_t p = 0; p < P.size(); ++p) mv += P.col(Field::mass)[p] * P.col(Field::vx)[p];
    const double v = mv / mass;
    // The leapfrog holds v^{n+1/2}: it belongs to the middle of the step just taken.
    const double t = sim->time() - 0.5 * sim->clock().dt_prev;
    const double err = std::abs(v - amplitude * std::cos(omega * t)) / amplitude;
    max_err = std::max(max_err, err);
    sum_sq += err * err;
    ++samples;
    if (samples > 1 && previous_v * v < 0.0) {
      crossings.push_back(previous_t + (t - previous_t) * previous_v / (previous_v - v));
    }
    previous_v = v;
    previous_t = t;
    worst_drift =
        std::max(worst_drift, std::abs(sim->energy().kinetic + sim->energy().internal - e0) / e0);
  });
  const double rms = std::sqrt(sum_sq / samples);
  ASSERT_EQ(crossings.size(), 10u);
  const double period = 2.0 * (crossings.back() - crossings.front()) / 9.0;
  std::printf("vibrating bar: com velocity error max %.3e rms %.3e, period %.4f s, drift %.2e\n",
              max_err, rms, period, worst_drift);
  EXPECT_LT(max_err, 4e-2);
  EXPECT_LT(rms, 2e-2);
  EXPECT_NEAR(period, 10.0, 0.05);
  EXPECT_LT(worst_drift, 1e-3);
}

// Problem 4: confined bar into a clamped wall. The moving mass shrinks at c_p, so the kinetic
// energy halves at L / (2 c_p) = 9.129 ms: the half point is the middle of the smeared front,
// so the grid's smearing cancels to first order (measured c_p = 108.8 m/s, -0.7 %, the residual
// lag of ~1/3 cell transit); 2 % bound. The plateau behind the front is -rho c_p v0 = -109.5 kPa
// (measured +0.26 %; 5 % as the engine test, MUSL ringing behind the front). The end is
// clamped (odd image), so after the release wave returns (2 L / c_p) the wall pulls the bar
// back: at 45 ms the moving fraction is 1 - (c_p t - 2 L) / L = 0.535 (measured 0.532).
TEST(VerificationScenes, WaveSpeedFromKineticEnergyAndPlateauStress) {
  const auto scene = load("wave-speed");
  auto sim = start(scene);
  const double cp = std::sqrt((1e7 / 1.5 + 4.0 / 3.0 * 4e6) / 1000.0);  // K = 6.67, G = 4 MPa
  const double ke0 = sim->energy().kinetic;
  double t_half = -1.0, previous_ke = ke0, previous_t = 0.0;
  run_to(*sim, 0.0125, [&] {
    const double ke = sim->energy().kinetic;
    if (t_half < 0.0 && ke < 0.5 * ke0) {
      t_half =
          previous_t + (sim->time() - previous_t) * (previous_ke - 0.5 * ke0) / (previous_ke - ke);
    }
    previous_ke = ke;
    previous_t = sim->time();
  });
  ASSERT_GT(t_half, 0.0);
  const double measured_cp = 2.0 / (2.0 * t_half);
  const auto [sxx, n] = mean_in(sim->particles(), Field::sxx, 0.1, 1.1);
  ASSERT_GT(n, 100);
  const double plateau = -1000.0 * cp * 1.0;
  run_to(*sim, scene.end_time);
  const double ke_end = sim->energy().kinetic / ke0;
  std::printf(
      "wave speed: c_p %.2f m/s (exact %.2f), plateau %.4g Pa (exact %.4g), KE(45 ms) %.3f\n",
      measured_cp, cp, sxx, plateau, ke_end);
  EXPECT_NEAR(measured_cp, cp, 0.02 * cp);
  EXPECT_NEAR(sxx / plateau, 1.0, 0.05);
  EXPECT_NEAR(ke_end, 1.0 - (cp * scene.end_time - 4.0) / 2.0, 0.05);
}

// Problem 3: colliding spheres, 20 cells across, t = 4. Bounds and reasons as the engine test:
// momentum at round-off (no boundary, no body force; 1e-12 of sum m|v|, measured 2e-14 kg m/s
// against 11.6), most kinetic energy stored during contact (< 50 %, measured 3.1 %; the timeseries,
// every 5 steps, shows 3.8 %), rebound (> 50 % back, measured 92.6 %; centres further apart than
// the 0.4 contact distance), total-energy error < 10 % (measured 0.49 %).
TEST(VerificationScenes, CollidingSpheresConserveMomentumAndRebound) {
  const auto scene = load("colliding-spheres");
  auto sim = start(scene);
  const auto& P0 = sim->particles();
  double sum_mv = 0.0;
  for (std::size_t p = 0; p < P0.size(); ++p) {
    sum_mv += P0.col(Field::mass)[p] *
              std::hypot(P0.col(Field::vx)[p], P0.col(Field::vy)[p], P0.col(Field::vz)[p]);
  }
  const double ke0 = sim->energy().kinetic;
  double ke_min = ke0, worst_p = 0.0, worst_error = 0.0;
  run_to(*sim, scene.end_time, [&] {
    const auto& P = sim->particles();
    std::array<double, 3> mom{};
    for (std::size_t p = 0; p < P.size(); ++p) {
      mom[0] += P.col(Field::mass)[p] * P.col(Field::vx)[p];
      mom[1] += P.col(Field::mass)[p] * P.col(Field::vy)[p];
      mom[2] += P.col(Field::mass)[p] * P.col(Field::vz)[p];
    }
    worst_p = std::max(worst_p, std::hypot(mom[0], mom[1], mom[2]));
    ke_min = std::min(ke_min, sim->energy().kinetic);
    worst_error = std::max(worst_error, std::abs(sim->energy().error()));
  });
  std::array<std::array<double, 4>, 2> centre{};  // sum m x, y, z and m per body
  const auto& P = sim->particles();
  for (std::size_t p = 0; p < P.size(); ++p) {
    auto& c = centre[static_cast<std::size_t>(P.col(IField::body)[p])];
    const double m = P.col(Field::mass)[p];
    c[0] += m * P.col(Field::x)[p];
    c[1] += m * P.col(Field::y)[p];
    c[2] += m * P.col(Field::z)[p];
    c[3] += m;
  }
  const double gap = std::hypot(centre[1][0] / centre[1][3] - centre[0][0] / centre[0][3],
                                centre[1][1] / centre[1][3] - centre[0][1] / centre[0][3],
                                centre[1][2] / centre[1][3] - centre[0][2] / centre[0][3]);
  std::printf(
      "colliding spheres: |p| max %.2e (sum m|v| %.3g), KE min %.3f end %.3f, energy "
      "error %.2e, gap %.3f m\n",
      worst_p, sum_mv, ke_min / ke0, sim->energy().kinetic / ke0, worst_error, gap);
  EXPECT_LT(worst_p, 1e-12 * sum_mv);
  EXPECT_LT(ke_min, 0.5 * ke0);
  EXPECT_GT(sim->energy().kinetic, 0.5 * ke0);
  EXPECT_GT(gap, 0.45);
  EXPECT_LT(worst_error, 0.10);
}

// Symmetry plane: the half-model scene reproduces the full-model scene. Particles are matched
// by their initial position (both lattices are the same global one); after 120 pinned steps
// velocities and stresses agree to 1e-9 relative, as in the engine test (the runs differ only in
// the order of the nodal sums; measured 4e-12 and 5e-11 at 0.1 m cells). Run at 0.1 m cells
// (--set): the identity holds at any resolution, and dt_max = 4e-5 s stays below the CFL step.
TEST(VerificationScenes, HalfModelReproducesFullModel) {
  const std::vector<std::string> coarse = {"solver.cell_size=0.1"};
  const auto full_scene = load("symmetry-plane-full", coarse);
  const auto half_scene = load("symmetry-plane-half", coarse);
  ASSERT_EQ(half_scene.symmetry_axis, 1);
  auto full = start(full_scene);
  auto half = start(half_scene);
  // Identify a point by its initial lattice position, rounded far below the spacing.
  using Key = std::tuple<long long, long long, long long>;
  auto key_of = [](const shatter::ParticleStore& P, std::size_t p) {
    return Key{std::llround(P.col(Field::x)[p] * 1e6), std::llround(P.col(Field::y)[p] * 1e6),
               std::llround(P.col(Field::z)[p] * 1e6)};
  };
  std::map<Key, std::int64_t> full_id;
  for (std::size_t p = 0; p < full->particles().size(); ++p) {
    full_id[key_of(full->particles(), p)] = full->particles().col(IField::id)[p];
  }
  std::map<std::int64_t, std::int64_t> partner;  // half id -> full id
  for (std::size_t p = 0; p < half->particles().size(); ++p) {
    const auto it = full_id.find(key_of(half->particles(), p));
    ASSERT_NE(it, full_id.end()) << "half-model point with no full-model twin";
    partner[half->particles().col(IField::id)[p]] = it->second;
  }
  ASSERT_EQ(2 * half->particles().size(), full->particles().size());
  for (int k = 0; k < 120; ++k) {
    full->step();
    half->step();
    ASSERT_EQ(full->clock().dt, half->clock().dt) << "step " << k;
  }
  const auto& F = full->particles();
  const auto& H = half->particles();
  std::map<std::int64_t, std::size_t> index;
  for (std::size_t p = 0; p < F.size(); ++p) index[F.col(IField::id)[p]] = p;
  double worst_v = 0.0, worst_s = 0.0, vmax = 0.0, smax = 0.0;
  for (std::size_t p = 0; p < F.size(); ++p) {
    vmax = std::max(vmax, std::abs(F.col(Field::vz)[p]));
    smax = std::max(smax, std::abs(F.col(Field::szz)[p]));
  }
  for (std::size_t q = 0; q < H.size(); ++q) {
    const std::size_t p = index.at(partner.at(H.col(IField::id)[q]));
    for (const Field f : {Field::vx, Field::vy, Field::vz}) {
      worst_v = std::max(worst_v, std::abs(H.col(f)[q] - F.col(f)[p]));
    }
    for (const Field f : {Field::sxx, Field::syy, Field::szz, Field::sxy, Field::syz, Field::sxz}) {
      worst_s = std::max(worst_s, std::abs(H.col(f)[q] - F.col(f)[p]));
    }
  }
  std::printf(
      "symmetry plane: velocity %.2e, stress %.2e (relative), KE half x2 / full - 1 = "
      "%.2e\n",
      worst_v / vmax, worst_s / smax, 2.0 * half->energy().kinetic / full->energy().kinetic - 1.0);
  EXPECT_LT(worst_v / vmax, 1e-9);
  EXPECT_LT(worst_s / smax, 1e-9);
  EXPECT_GT(smax, 1e5);  // the impact did load the block
  EXPECT_NEAR(2.0 * half->energy().kinetic / full->energy().kinetic, 1.0, 1e-9);
}

// Problem 5a: Sod, 200 cells, t = 0.2, star state of the exact Riemann solution (Toro Table
// 4.3). 3 %: the viscosity smears the shock over ~3 cells and the transfers add O(h) noise to a
// constant state. Measured p* -1.8 %, u* -0.3 %, rho*L -1.4 %, rho*R -0.3 %.
TEST(VerificationScenes, SodStarStateMatchesExactRiemannSolution) {
  const auto scene = load("sod-shock-tube");
  auto sim = start(scene);
  run_to(*sim, scene.end_time);
  const auto& P = sim->particles();
  const auto [p_star, np] = mean_in(P, Field::pressure, 0.52, 0.66);
  const auto [u_star, nu] = mean_in(P, Field::vx, 0.52, 0.80);
  const auto [rho_l, nl] = mean_in(P, Field::rho, 0.52, 0.66);
  const auto [rho_r, nr] = mean_in(P, Field::rho, 0.72, 0.82);
  ASSERT_GT(std::min({np, nu, nl, nr}), 10);
  std::printf(
      "Sod: p* %.5f (0.30313), u* %.5f (0.92745), rho*L %.5f (0.42632), rho*R %.5f "
      "(0.26557)\n",
      p_star, u_star, rho_l, rho_r);
  EXPECT_NEAR(p_star, 0.30313, 0.03 * 0.30313);
  EXPECT_NEAR(u_star, 0.92745, 0.03 * 0.92745);
  EXPECT_NEAR(rho_l, 0.42632, 0.03 * 0.42632);
  EXPECT_NEAR(rho_r, 0.26557, 0.03 * 0.26557);
}

// Planar impact of aluminium 6061 at 2 x 500 m/s: the shocked state is the principal Hugoniot
// at up = 500 m/s (material probe; 8.028 GPa as the scene header says). Pressure within 3 %
// (measured -0.3 %), material at rest (< 3 % of u0, measured 2 m/s), front speed from the 10
// and 25 us positions within 4 % (each located to ~one point spacing; measured -0.05 %).
TEST(VerificationScenes, PlanarImpactReachesHugoniotState) {
  const auto scene = load("planar-impact-aluminium");
  const double up[] = {500.0};
  const auto hug =
      shatter::hugoniot(shatter::MaterialCatalogue::builtin().get("aluminium_6061"), up).front();
  EXPECT_NEAR(hug.p, 8.028e9, 1e6);  // the number quoted in the scene header
  auto sim = start(scene);
  const double h = scene.solver.cell_size, half_rho = 0.5 * (2703.0 + hug.rho);
  auto front = [&] {
    const auto& P = sim->particles();
    double x = 0.0;
    for (std::size_t p = 0; p < P.size(); ++p) {
      if (P.col(Field::rho)[p] > half_rho) x = std::max(x, P.col(Field::x)[p]);
    }
    return x;
  };
  run_to(*sim, 10e-6);
  const double x1 = front();
  run_to(*sim, 25e-6);
  const double x2 = front();
  const double speed = (x2 - x1) / 15e-6;
  const auto& P = sim->particles();
  double psum = 0.0, vsum = 0.0;
  int n = 0;
  for (std::size_t p = 0; p < P.size(); ++p) {
    const double ax = std::abs(P.col(Field::x)[p]);
    if (ax > 3 * h && ax < x2 - 3 * h) {
      psum += P.col(Field::pressure)[p];
      vsum += std::abs(P.col(Field::vx)[p]);
      ++n;
    }
  }
  ASSERT_GT(n, 100);
  std::printf("planar impact: p %.4g Pa (Hugoniot %.4g), front %.0f m/s (Us - up %.0f), |v| %.2f\n",
              psum / n, hug.p, speed, hug.us - hug.up, vsum / n);
  EXPECT_NEAR(psum / n, hug.p, 0.03 * hug.p);
  EXPECT_LT(vsum / n, 0.03 * 500.0);
  EXPECT_NEAR(speed, hug.us - hug.up, 0.04 * (hug.us - hug.up));
}

// Problem 5b: planar Noh, gamma = 5/3, t = 0.6: shock at t/3 = 0.2, behind it rho = 4,
// p = 4/3, E = 1/2, at rest. The shocked gas (compressed 4x, ~8 points per cell along x) rings at
// the cell scale (rho 3.1 to 5.0 between 0.05 and 0.17, standard deviation 0.64) around the right
// mean, so the checks are on means over 24 cells: E is the steadiest (measured +0.17 %, bound
// 2 %), rho +3.1 % (bound 5 %), p +6.9 % (bound 10 %: p = (gamma - 1) rho E, and rho and E
// ring in phase), |v| 0.03 (bound 0.1 of v0), shock position +0.0024 (bound 2 cells).
TEST(VerificationScenes, NohShockPositionAndPostShockState) {
  const auto scene = load("noh-planar");
  auto sim = start(scene);
  run_to(*sim, scene.end_time);
  const auto& P = sim->particles();
  double shock = 0.0;
  for (std::size_t p = 0; p < P.size(); ++p) {
    if (P.col(Field::rho)[p] > 2.5) shock = std::max(shock, P.col(Field::x)[p]);
  }
  const auto [rho, n] = mean_in(P, Field::rho, 0.05, 0.17);
  const auto [pressure, n2] = mean_in(P, Field::pressure, 0.05, 0.17);
  const auto [energy, n3] = mean_in(P, Field::energy, 0.05, 0.17);
  const auto [speed, n4] = mean_in(P, Field::vx, 0.05, 0.17, true);
  ASSERT_GT(n, 100);
  std::printf("Noh: shock %.4f (0.2), rho %.4f (4), p %.4f (1.3333), E %.4f (0.5), |v| %.4f\n",
              shock, rho, pressure, energy, speed);
  EXPECT_NEAR(shock, 0.2, 2 * scene.solver.cell_size);
  EXPECT_NEAR(energy, 0.5, 0.02 * 0.5);
  EXPECT_NEAR(rho, 4.0, 0.05 * 4.0);
  EXPECT_NEAR(pressure, 4.0 / 3.0, 0.10 * 4.0 / 3.0);
  EXPECT_LT(speed, 0.1);
}
