// Elastic wave speed (reference/verification-problems.md #4): a laterally confined bar moving
// into a fixed wall launches a compression wave at c_p = sqrt((K + 4G/3) / rho); the gauge
// halfway along must see it arrive at x / c_p with the plateau stress rho c_p v0.
#include <gtest/gtest.h>

#include <memory>

#include "shatter/material/linear_elastic.hpp"
#include "shatter/mpm/simulation.hpp"
#include "support/lattice.hpp"

using namespace shatter;
using Eigen::Vector3d;

namespace {

struct Arrival {
  double time, exact, plateau_ratio, transit;
};

// Runs the bar at cell size h; returns when the half-amplitude of the front passed the gauge.
Arrival run_bar(double h) {
  const double rho = 1000.0, E = 1e7, nu = 0.25, v0 = 1.0;
  auto mat = std::make_shared<LinearElastic>(rho, E, nu);
  const double cp = mat->longitudinal_speed(rho);  // 109.5 m/s
  ParticleStore s;
  test::add_box(s, 0, Vector3d(0, 0, 0), Vector3d(2.0, h, h), h / 2, rho, Vector3d(-v0, 0, 0));
  SolverConfig cfg;
  cfg.cell_size = h;
  cfg.domain.lo = Vector3d(0, 0, 0);
  cfg.domain.hi = Vector3d(4.0, h, h);
  cfg.domain.faces = {BoundaryKind::fixed, BoundaryKind::none, BoundaryKind::slip,
                      BoundaryKind::slip,  BoundaryKind::slip, BoundaryKind::slip};
  Simulation sim(cfg, std::move(s), {mat}, 1);

  // Gauge: the particles nearest x = 1 m (their ids, since the engine re-orders particles).
  const double gauge_x = 1.0 + h / 4;
  std::vector<std::int64_t> gauge_ids;
  for (std::size_t p = 0; p < sim.particles().size(); ++p) {
    if (std::abs(sim.particles().col(Field::x)[p] - gauge_x) < 1e-9) {
      gauge_ids.push_back(sim.particles().col(IField::id)[p]);
    }
  }
  EXPECT_EQ(gauge_ids.size(), 4u);
  auto gauge_stress = [&] {
    const auto& P = sim.particles();
    double sum = 0;
    for (std::size_t p = 0; p < P.size(); ++p) {
      for (const auto id : gauge_ids) {
        if (P.col(IField::id)[p] == id) sum += P.col(Field::sxx)[p];
      }
    }
    return sum / static_cast<double>(gauge_ids.size());
  };
  const double plateau = -rho * cp * v0;  // acoustic impedance times particle velocity
  double arrival = -1.0;
  const double t_end = 1.4 / cp;  // before the reflection from the free end returns
  double late = 0.0;
  while (sim.time() < t_end) {
    sim.step();
    const double sxx = gauge_stress();
    if (arrival < 0 && sxx < 0.5 * plateau) arrival = sim.time();
    late = sxx;
  }
  return {arrival, gauge_x / cp, late / plateau, h / cp};
}

}  // namespace

TEST(WaveSpeed, CompressionWaveArrivesAtLongitudinalSpeed) {
  const Arrival coarse = run_bar(0.02);
  const Arrival fine = run_bar(0.01);
  ASSERT_GT(coarse.time, 0.0) << "no wave reached the gauge";
  ASSERT_GT(fine.time, 0.0) << "no wave reached the gauge";
  // The grid smears the front over ~2 cells and the wall needs about one cell to stop the
  // material, so the half-amplitude point lags by about one cell transit time h / c_p (measured
  // 1.2 h / c_p, 2% of the arrival time at h = 2 cm). Bound: 2 h / c_p.
  EXPECT_NEAR(coarse.time, coarse.exact, 2 * coarse.transit);
  EXPECT_NEAR(fine.time, fine.exact, 2 * fine.transit);
  // The lag is a discretisation error and must shrink with h. The explicit grid is dispersive, so
  // the half-amplitude point of the step front lags like an Airy front, ~ t^(1/3) h^(2/3):
  // halving h should cut it to 2^(-2/3) = 0.63 (measured 0.73). Bound 0.85; a wrong modulus or
  // density gives a lag that grows linearly in time and does not shrink with h.
  EXPECT_LT(std::abs(fine.time - fine.exact), 0.85 * std::abs(coarse.time - coarse.exact));
  // Plateau behind the front: rho c_p v0 within 5% (MUSL dissipation and post-front ringing).
  EXPECT_NEAR(coarse.plateau_ratio, 1.0, 0.05);
  EXPECT_NEAR(fine.plateau_ratio, 1.0, 0.05);
}
