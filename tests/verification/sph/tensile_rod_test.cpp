// The tensile rod of Benz & Asphaug (1995, Sec. 5.1) with SPH: a basalt cylinder, 1 cm radius x
// 4 cm, pulled at both ends under a uniform, slowly increasing ("equilibrated") extension. Cracks
// nucleate at the weakest explicit flaws (BA95 Eq. 20) and grow across the load; BA95 measured
// their speed within 5 % of c_g = 0.4 c_p and found more cracks at the faster pull.
//
// Set-up: the rod between two grips (basalt cylinders 4 mm long, no damage) that move at
// +/- eps_dot z_0 (prescribed by the scene key body.NAME.driven); the rod starts with
// the same linear velocity field v_z = eps_dot z_0, so the extension is uniform from the start
// and no wave is launched. Materials: the catalogue's basalt (Tillotson, linear hardening,
// E = 53.1 GPa, Poisson 0.15: c_p = sqrt((A + 4 G / 3) / rho) = 4616 m/s with the Tillotson bulk
// modulus A = 26.7 GPa, so c_g = 1846 m/s), Grady-Kipp damage with BA95's explicit flaws, m =
// 8.5, k = 3e39 m^-3 (the MPM paper's Table 1 basalt; BA95 give no rod values).
//
// Gauges: the time each point's damage first reaches 1 (failed), the failed fraction, the
// fragments (BA95 Sec. 4.4: friends within one h, veneer), and the crack speed: the first point
// to fail nucleates a crack; the points that fail within one spacing of its plane (|z - z_0| <
// s) are that crack; in rings one spacing wide around the nucleus the earliest failure marks the
// front, and the least-squares slope of the front's distance against its time is the speed.
// A second estimator takes, per ring, the time half of the ring's rod points have failed (a
// median, insensitive to early failures ahead of the tip) and fits the ring radius against it.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "shatter/fracture/fragments.hpp"
#include "shatter/scene/build.hpp"
#include "shatter/scene/scene.hpp"
#include "shatter/sph/solver.hpp"

namespace shatter::sph {
namespace {

constexpr double kCp = 4616.0;  // m/s, sqrt((26.7e9 + 4/3 * 23.09e9) / 2700)
constexpr double kCg = 0.4 * kCp;

// method: "sph" or "mpm" (the same rod, grips and flaws; the study's SHATTER_ROD_METHOD).
std::string rod_scene(double spacing, std::uint64_t seed, const std::string& method) {
  return fmt::format(R"(
[solver]
method = "{method}"
cell_size = {cell}
end_time = 1.0
[body.rod]
shape = "cylinder"
centre = [0.0, 0.0, 0.0]
axis = [0.0, 0.0, 1.0]
radius = 0.01
length = 0.04
material = "basalt"
[body.rod.damage]
model = "grady_kipp"
weibull_m = 8.5
weibull_k = 3.0e39
explicit_flaws = 1
seed = {seed}
[body.grip_lo]
shape = "cylinder"
centre = [0.0, 0.0, -0.022]
axis = [0.0, 0.0, 1.0]
radius = 0.01
length = 0.004
material = "basalt"
driven = true
[body.grip_hi]
shape = "cylinder"
centre = [0.0, 0.0, 0.022]
axis = [0.0, 0.0, 1.0]
radius = 0.01
length = 0.004
material = "basalt"
driven = true
)",
                     fmt::arg("cell", 2.0 * spacing), fmt::arg("seed", seed),
                     fmt::arg("method", method));
}

struct RodResult {
  std::size_t points = 0, steps = 0;
  double failed_fraction = 0.0;  // of the rod's points, at the end
  double failure_strain = 0.0;   // eps_dot t at the first failure
  std::size_t fragments = 0;     // holding >= 5 % of the rod's mass
  double largest = 0.0;          // largest fragment / rod mass
  double crack_speed = 0.0;      // m/s (NaN if fewer than 4 points in the first crack)
  // Second estimator: per ring, the time by which half of the ring's rod points have failed
  // (the crack's bulk, not its earliest failure); slope of ring radius against that time.
  double crack_speed_half = 0.0;  // m/s (NaN if fewer than 3 rings are half failed)
  std::size_t half_rings = 0;     // rings in that fit
  std::size_t crack_points = 0;
  double crack_r_max = 0.0;
};

// Pulls the rod at eps_dot until t_end.
RodResult pull(double spacing, double eps_dot, double t_end, std::uint64_t seed, int threads,
               const std::string& method = "sph") {
  const scene::Scene s = scene::parse_scene(rod_scene(spacing, seed, method), "rod.toml");
  scene::BuiltScene b = scene::build(s);
  ParticleStore& P0 = b.particles;
  std::int64_t rod = -1;
  for (std::size_t g = 0; g < s.bodies.size(); ++g) {
    if (s.bodies[g].name == "rod") rod = static_cast<std::int64_t>(g);
  }
  std::vector<double> z0(P0.size());
  for (std::size_t p = 0; p < P0.size(); ++p) {
    z0[p] = P0.col(Field::z)[p];
    P0.col(Field::vz)[p] = eps_dot * z0[p];  // uniform extension from the start
  }
  auto solver = scene::make_solver(s, std::move(b.particles), b.materials, threads);
  // Grips: `driven = true` (the scene key) holds every grip point at its initial velocity,
  // v = (0, 0, eps_dot z_0), in either method (src/mpm/driven.hpp; SPH: the velocity constraint).

  const ParticleStore& P = solver->particles();
  std::vector<double> t_fail(P0.size() > 0 ? z0.size() : 0, -1.0);
  double rod_mass = 0.0;
  std::size_t rod_points = 0;
  for (std::size_t p = 0; p < P.size(); ++p) {
    if (P.col(IField::body)[p] != rod) continue;
    rod_mass += P.col(Field::mass)[p];
    ++rod_points;
  }
  while (solver->time() < t_end) {
    solver->step();
    const auto D = P.col(Field::damage);
    const auto id = P.col(IField::id);
    for (std::size_t p = 0; p < P.size(); ++p) {
      const auto i = static_cast<std::size_t>(id[p]);
      if (t_fail[i] < 0.0 && D[p] >= 1.0) t_fail[i] = solver->time();
    }
  }

  RodResult r;
  r.points = rod_points;
  r.steps = solver->clock().step;
  // Initial positions by id, from the initial z and the current x, y (lateral motion is tiny).
  std::vector<std::size_t> at(z0.size());
  for (std::size_t p = 0; p < P.size(); ++p) at[static_cast<std::size_t>(P.col(IField::id)[p])] = p;
  std::size_t failed = 0, first = z0.size();
  for (std::size_t i = 0; i < z0.size(); ++i) {
    if (t_fail[i] < 0.0) continue;
    ++failed;
    if (first == z0.size() || t_fail[i] < t_fail[first]) first = i;
  }
  r.failed_fraction = static_cast<double>(failed) / static_cast<double>(rod_points);
  r.crack_speed = std::nan("");
  r.crack_speed_half = std::nan("");
  if (first < z0.size()) {
    r.failure_strain = eps_dot * t_fail[first];
    const std::size_t q = at[first];
    const double x0 = P.col(Field::x)[q], y0 = P.col(Field::y)[q];
    // The front: in rings of one spacing around the nucleus, the earliest failure (later
    // failures behind the front, as the crack opens or other flaws join, do not slow it).
    std::vector<double> ring_t, ring_r;
    for (std::size_t i = 0; i < z0.size(); ++i) {
      if (t_fail[i] < 0.0 || std::abs(z0[i] - z0[first]) >= spacing) continue;
      const std::size_t p = at[i];
      const double dx = P.col(Field::x)[p] - x0, dy = P.col(Field::y)[p] - y0;
      const double rr = std::sqrt(dx * dx + dy * dy);
      const auto ring = static_cast<std::size_t>(rr / spacing);
      if (ring >= ring_t.size()) {
        ring_t.resize(ring + 1, -1.0);
        ring_r.resize(ring + 1, 0.0);
      }
      if (ring_t[ring] < 0.0 || t_fail[i] < ring_t[ring]) {
        ring_t[ring] = t_fail[i];
        ring_r[ring] = rr;
      }
      r.crack_r_max = std::max(r.crack_r_max, rr);
      ++r.crack_points;
    }
    const auto slope = [](const std::vector<double>& t, const std::vector<double>& x) {
      double st = 0, sx = 0, stt = 0, stx = 0;
      std::size_t n = 0;
      for (std::size_t k = 0; k < t.size(); ++k) {
        if (t[k] < 0.0) continue;
        st += t[k];
        sx += x[k];
        stt += t[k] * t[k];
        stx += t[k] * x[k];
        ++n;
      }
      const double dn = static_cast<double>(n);
      return n >= 3 && stt * dn - st * st > 0.0 ? (stx * dn - st * sx) / (stt * dn - st * st)
                                                : std::nan("");
    };
    r.crack_speed = slope(ring_t, ring_r);
    // Second estimator: every rod point of the crack's band (failed or not) by ring; a ring's
    // time is the median failure time of its points (unfailed points count as never), defined
    // once at least half of them have failed; its radius the ring's mean radius. Earliest
    // failures ahead of the tip (flaws the tip's stress opens early) do not move a median.
    std::vector<std::vector<double>> ring_times;
    std::vector<double> ring_sum_r;
    for (std::size_t i = 0; i < z0.size(); ++i) {
      const std::size_t p = at[i];
      if (P.col(IField::body)[p] != rod || std::abs(z0[i] - z0[first]) >= spacing) continue;
      const double dx = P.col(Field::x)[p] - x0, dy = P.col(Field::y)[p] - y0;
      const double rr = std::sqrt(dx * dx + dy * dy);
      const auto ring = static_cast<std::size_t>(rr / spacing);
      if (ring >= ring_times.size()) {
        ring_times.resize(ring + 1);
        ring_sum_r.resize(ring + 1, 0.0);
      }
      ring_times[ring].push_back(t_fail[i] < 0.0 ? 1e300 : t_fail[i]);
      ring_sum_r[ring] += rr;
    }
    std::vector<double> half_t(ring_times.size(), -1.0), half_r(ring_times.size(), 0.0);
    for (std::size_t k = 0; k < ring_times.size(); ++k) {
      auto& ts = ring_times[k];
      if (ts.size() < 4) continue;  // too few points for a median
      std::sort(ts.begin(), ts.end());
      const double med = ts[(ts.size() - 1) / 2];
      if (med > 1e299) continue;  // less than half of the ring failed
      half_t[k] = med;
      half_r[k] = ring_sum_r[k] / static_cast<double>(ts.size());
      ++r.half_rings;
    }
    r.crack_speed_half = slope(half_t, half_r);
  }

  ParticleStore copy = P;
  FragmentSearchSpec spec;
  spec.method = "friends_of_friends";
  spec.smoothing_factor = s.sph.h_factor;
  spec.damage_threshold = 1.0;
  const FragmentCatalogue cat = find_fragments(copy, spec);
  for (const Fragment& f : cat.fragments) {
    if (f.mass >= 0.05 * rod_mass) ++r.fragments;
  }
  // The grips are in the catalogue too (their own fragments once the rod has broken): count
  // fragments against the rod's mass only, as upper bounds.
  r.largest = cat.fragments.empty() ? 0.0 : cat.fragments[0].mass / cat.total_mass;
  return r;
}

void print(const char* label, double eps_dot, const RodResult& r) {
  std::printf(
      "%s eps_dot %.3g/s: %zu rod points, %zu steps, first failure at strain %.3g, failed %.1f%%, "
      "%zu fragments >= 5%% of the rod, largest %.3f of all, first crack %zu points to r = %.1f "
      "mm, speed %.0f m/s = %.2f c_g (earliest per ring); %.2f c_g (half-failed time per ring, "
      "%zu rings)\n",
      label, eps_dot, r.points, r.steps, r.failure_strain, 100.0 * r.failed_fraction, r.fragments,
      r.largest, r.crack_points, 1e3 * r.crack_r_max, r.crack_speed, r.crack_speed / kCg,
      r.crack_speed_half / kCg, r.half_rings);
}

// Weakest flaw of the explicit set: eps_1 = (1 / (k V))^(1/m), V = pi (1 cm)^2 4 cm:
// (1 / 3.77e34)^(1/8.5) = 8.6e-5.
constexpr double kEps1 = 8.6e-5;
// Pull rates 6x apart (BA95 do not give theirs). A crack crosses the rod's 2 cm in
// 2 cm / c_g = 11 us; at 10/s the strain rises by 1.1e-4 ~ eps_1 meanwhile, so few flaws open
// before the first cracks relieve the rod; at 60/s six times more strain is added.
constexpr double kSlow = 10.0, kFast = 60.0;
// Both to the time the slow pull reaches 3 eps_1 (25.8 us, ~370 steps at 2.5 mm).
constexpr double kEnd = 3.0 * kEps1 / kSlow;

// Short version (CI): 2.5 mm spacing (832 rod points), the two rates. Checks that the rod
// breaks across the load and that the faster pull fails more of it (BA95 Fig. 2); the crack
// speed needs the study's resolution.
TEST(SphTensileRod, RodBreaksAcrossTheLoadAndTheFasterPullFailsMore) {
  constexpr double kSpacing = 2.5e-3;
  const RodResult slow = pull(kSpacing, kSlow, kEnd, 1, 2);
  const RodResult fast = pull(kSpacing, kFast, kEnd, 1, 2);
  print("slow", kSlow, slow);
  print("fast", kFast, fast);
  // The first failure comes after the weakest flaw activates (eps_1) and its damage has grown;
  // at the faster pull the strain rises further while the crack grows. Bounds: [1, 2.5] eps_1.
  EXPECT_GE(slow.failure_strain, kEps1);
  EXPECT_LE(slow.failure_strain, 2.5 * kEps1);
  EXPECT_GT(fast.failure_strain, slow.failure_strain);
  // Broken: at least two pieces of >= 5 % of the rod each.
  EXPECT_GE(slow.fragments, 2u);
  // More failure at the faster pull (measured 37 % and 79 %, 3 and 5 pieces).
  EXPECT_GT(fast.failed_fraction, slow.failed_fraction);
  EXPECT_GE(fast.fragments, slow.fragments);
  // The first crack's front speed, 28 points at this resolution: measured 1.12 c_g (BA95: within
  // 5 % of c_g at ~50 000 particles; here it depends on the resolution: 1.4-1.9 c_g at 1.25 mm,
  // docs/validation-sph.md). Bounds [0.6, 1.5] c_g: a crack that runs at the sound speed
  // (c_p = 2.5 c_g, a numerical fracture) or stalls fails them.
  EXPECT_GT(slow.crack_speed, 0.6 * kCg);
  EXPECT_LT(slow.crack_speed, 1.5 * kCg);
}

// Study (not in CI): the two rates at SHATTER_ROD_SPACING (default 1.25 mm, ~6 500 rod points)
// over SHATTER_ROD_SEEDS flaw seeds (default 3), all threads. studies/sph_vs_mpm/sph_tensile_rod.py
// runs it and tabulates the lines it prints.
TEST(SphTensileRod, DISABLED_Study) {
  const char* env = std::getenv("SHATTER_ROD_SPACING");
  const double spacing = env != nullptr ? std::atof(env) : 1.25e-3;
  const char* seeds_env = std::getenv("SHATTER_ROD_SEEDS");
  const int seeds = seeds_env != nullptr ? std::atoi(seeds_env) : 3;
  // SHATTER_ROD_END_FACTOR: end time in units of kEnd (a longer pull, to see the rod break).
  const char* end_env = std::getenv("SHATTER_ROD_END_FACTOR");
  // SHATTER_ROD_METHOD: "sph" (default) or "mpm" (the same scene; MPM cell = 2 spacings).
  const char* method_env = std::getenv("SHATTER_ROD_METHOD");
  const std::string method = method_env != nullptr ? method_env : "sph";
  const double end = kEnd * (end_env != nullptr ? std::atof(end_env) : 1.0);
  for (int seed = 1; seed <= seeds; ++seed) {
    for (const double rate : {kSlow, kFast}) {
      const RodResult r = pull(spacing, rate, end, static_cast<std::uint64_t>(seed), 0, method);
      std::printf(
          "ROD spacing=%g seed=%d rate=%g points=%zu steps=%zu eps_first=%.4g "
          "failed=%.4f fragments=%zu largest=%.4f crack_points=%zu crack_r=%.4g "
          "crack_speed=%.1f crack_speed_half=%.1f half_rings=%zu cg=%.1f\n",
          spacing, seed, rate, r.points, r.steps, r.failure_strain, r.failed_fraction, r.fragments,
          r.largest, r.crack_points, r.crack_r_max, r.crack_speed, r.crack_speed_half, r.half_rings,
          kCg);
      std::fflush(stdout);
    }
  }
}

}  // namespace
}  // namespace shatter::sph
