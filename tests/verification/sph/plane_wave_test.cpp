// Elastic wave speed with SPH (issue 10, Validation "Elastic waves"). Two identical elastic
// blocks (verification catalogue `wave_elastic`: E = 10 MPa, Poisson 0.25, rho = 1000 kg/m^3)
// meet head-on at +/- v0 on the plane x = 0. A compression front runs into each block at
//   c_p = sqrt((K + 4 G / 3) / rho) = sqrt((6.667 + 5.333) MPa / 1000) = 109.545 m/s
// (uniaxial strain: the front's head is not reached by the release from the lateral free
// surfaces). The material behind the front is at rest, the material ahead still moves at -v0.
// Gauge: on the central columns of the right block, the Lagrangian position (initial x) where vx
// crosses -v0/2, at two times; the speed is the difference quotient, so the start-up offset
// drops out.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "shatter/scene/build.hpp"
#include "shatter/scene/scene.hpp"

namespace shatter::sph {
namespace {

constexpr double kCp = 109.54451150103323;  // sqrt(12e6 / 1000)
constexpr double kV0 = 0.1;                 // m/s: strain v0 / c_p ~ 1e-3, linear
constexpr double kL = 0.2;                  // m, length of each block
// m, width and height: wide enough that the release from the lateral free surfaces does not
// reach the axis near the front before the second gauge time (with 0.16 m the front measured
// 100 m/s at 0.01 m spacing: the bar speed sqrt(E / rho), not c_p).
constexpr double kW = 0.32;
constexpr double kX1 = 0.04, kX2 = 0.12;  // m, front positions at the two gauge times

// Front position (Lagrangian) on the central columns, or NaN if not found.
double front(const ParticleStore& P, const std::vector<double>& x0, double spacing) {
  const auto vx = P.col(Field::vx), y = P.col(Field::y), z = P.col(Field::z);
  const auto body = P.col(IField::body), id = P.col(IField::id);
  // Central columns: |y - W/2|, |z - W/2| below one spacing (identified by their initial x and
  // the current y, z, which barely move under uniaxial strain on the axis).
  std::vector<std::pair<double, double>> column;  // (x0, vx)
  std::vector<std::vector<std::pair<double, double>>> columns;
  std::vector<std::pair<double, double>> keys;
  for (std::size_t p = 0; p < P.size(); ++p) {
    if (body[p] != 1) continue;
    if (std::abs(y[p] - 0.5 * kW) > spacing || std::abs(z[p] - 0.5 * kW) > spacing) continue;
    const double ky = std::round(y[p] / spacing), kz = std::round(z[p] / spacing);
    std::size_t c = 0;
    while (c < keys.size() && !(keys[c].first == ky && keys[c].second == kz)) ++c;
    if (c == keys.size()) {
      keys.emplace_back(ky, kz);
      columns.emplace_back();
    }
    columns[c].emplace_back(x0[static_cast<std::size_t>(id[p])], vx[p]);
  }
  double sum = 0.0;
  int n = 0;
  for (auto& col : columns) {
    std::sort(col.begin(), col.end());
    // From the far end (moving at -v0) inward: the first point with vx > -v0/2.
    for (std::size_t k = col.size() - 1; k > 0; --k) {
      const auto& [xa, va] = col[k - 1];
      const auto& [xb, vb] = col[k];
      if (va > -0.5 * kV0 && vb <= -0.5 * kV0) {
        sum += xa + (xb - xa) * (-0.5 * kV0 - va) / (vb - va);
        ++n;
        break;
      }
    }
  }
  return n > 0 ? sum / n : std::nan("");
}

struct Measured {
  double cp = 0.0;
  std::size_t points = 0;
  std::uint64_t steps = 0;
};

Measured wave_speed(double spacing, int threads, double h_factor = 1.2,
                    const std::string& sph_lines = "") {
  const std::string text = fmt::format(R"(
catalogue = "materials.toml"
[solver]
method = "sph"
cell_size = {0}
end_time = 1.0
[solver.sph]
h_factor = {6}
{7}
[body.left]
shape = "box"
lo = [{1}, 0.0, 0.0]
hi = [0.0, {2}, {2}]
material = "wave_elastic"
velocity = [{3}, 0.0, 0.0]
points_per_cell = 1
[body.right]
shape = "box"
lo = [0.0, 0.0, 0.0]
hi = [{4}, {2}, {2}]
material = "wave_elastic"
velocity = [{5}, 0.0, 0.0]
points_per_cell = 1
)",
                                       spacing, -kL, kW, kV0, kL, -kV0, h_factor, sph_lines);
  const scene::Scene s = scene::parse_scene(
      text, "plane-wave.toml", {}, std::string(SHATTER_SOURCE_DIR) + "/scenes/verification");
  scene::BuiltScene b = scene::build(s);
  std::vector<double> x0(b.particles.size());
  for (std::size_t p = 0; p < b.particles.size(); ++p) {
    x0[static_cast<std::size_t>(b.particles.col(IField::id)[p])] = b.particles.col(Field::x)[p];
  }
  auto sim = scene::make_solver(s, std::move(b.particles), b.materials, threads);
  Measured m;
  m.points = sim->particles().size();
  sim->advance_to(kX1 / kCp);
  const double f1 = front(sim->particles(), x0, spacing);
  sim->advance_to(kX2 / kCp);
  const double f2 = front(sim->particles(), x0, spacing);
  m.cp = (f2 - f1) / ((kX2 - kX1) / kCp);
  m.steps = sim->clock().step;
  return m;
}

TEST(SphPlaneWave, CompressionFrontRunsAtTheLongitudinalSpeed) {
  const Measured m = wave_speed(0.02, 2);
  const double err = m.cp / kCp - 1.0;
  std::printf(
      "SPH plane wave, spacing 0.02 m (%zu points, %llu steps): c = %.3f m/s, error %+.2f%%\n",
      m.points, static_cast<unsigned long long>(m.steps), m.cp, 100.0 * err);
  // Measured -5.8 % at this spacing (the front gauged over 4 spacings only), -3.2 % at 0.01 m
  // (DISABLED_ResolutionStudy, docs/validation-sph.md). Two parts: the kernel's lattice
  // deficiency at h = 1.2 s (the discrete gradient reads 1.8 % low, c_eff = 0.982 c_p; it does
  // not shrink with the spacing, only with h / s), and the gauge on a front that the viscosity
  // and SPH dispersion smear over several spacings, which shrinks with the spacing. Bound 8 %:
  // fails if the front speed is off by more than these two account for.
  EXPECT_LT(std::abs(err), 0.08);
  EXPECT_LT(err, 0.0);  // both effects slow the measured front
}

// The same with the Morris & Monaghan (1997) viscosity switch and the normalized continuity
// (issue 11): the front is a weak compression (strain 1e-3, |div v| tau ~ 1e-2 in the front), so
// alpha decays toward alpha_min = 0.1 ahead of it and the front is less damped; it must still
// run at c_p within the same bound.
TEST(SphPlaneWave, CompressionFrontRunsAtTheLongitudinalSpeedWithTheViscositySwitch) {
  const Measured m = wave_speed(
      0.02, 2, 1.2, "viscosity_switch = \"morris_monaghan\"\ncontinuity = \"normalized\"\n");
  const double err = m.cp / kCp - 1.0;
  std::printf(
      "SPH plane wave with the switch, spacing 0.02 m (%zu points, %llu steps): c = %.3f "
      "m/s, error %+.2f%%\n",
      m.points, static_cast<unsigned long long>(m.steps), m.cp, 100.0 * err);
  // Bound as above (8 %: the lattice deficiency and the gauge on a smeared front).
  EXPECT_LT(std::abs(err), 0.08);
}

// The resolution study of docs/validation-sph.md (about a minute on 2 cores, so not in CI):
//   unit... verification_sph --gtest_also_run_disabled_tests --gtest_filter='*Study*'
TEST(SphPlaneWave, DISABLED_ResolutionStudy) {
  for (const double h_factor : {1.2, 1.3}) {
    for (const double spacing : {0.02, 0.01, 0.0066666666666666671}) {
      const Measured m = wave_speed(spacing, 2, h_factor);
      const double err = m.cp / kCp - 1.0;
      std::printf(
          "h_factor %.1f, spacing %.4f m: %zu points, %llu steps, c = %.3f m/s, error %+.3f%%\n",
          h_factor, spacing, m.points, static_cast<unsigned long long>(m.steps), m.cp, 100.0 * err);
      EXPECT_LT(std::abs(err), 0.1);
    }
  }
}

}  // namespace
}  // namespace shatter::sph
