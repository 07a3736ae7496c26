// Two elastic spheres colliding (Sulsky et al. 1994, reference/verification-problems.md #3, 3D
// version): no closed form, but exact conservation laws and a qualitative history to check.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <tuple>

#include "shatter/material/linear_elastic.hpp"
#include "shatter/mpm/simulation.hpp"
#include "support/lattice.hpp"

using namespace shatter;
using Eigen::Vector3d;

namespace {

ParticleStore two_spheres(double spacing) {
  ParticleStore s;
  const Vector3d v(0.1, 0.1, 0.1);
  test::add_sphere(s, 0, Vector3d(0.2, 0.2, 0.2), 0.2, spacing, 1000.0, v, 0);
  test::add_sphere(s, 0, Vector3d(0.8, 0.8, 0.8), 0.2, spacing, 1000.0, -v, 1);
  return s;
}

Vector3d body_centre(const ParticleStore& P, int body) {
  Vector3d c = Vector3d::Zero();
  double m = 0;
  for (std::size_t p = 0; p < P.size(); ++p) {
    if (P.col(IField::body)[p] != body) continue;
    const double mp = P.col(Field::mass)[p];
    c += mp * Vector3d(P.col(Field::x)[p], P.col(Field::y)[p], P.col(Field::z)[p]);
    m += mp;
  }
  return c / m;
}

class CollidingSpheres : public ::testing::TestWithParam<std::tuple<ShapeKind, TransferKind>> {};

}  // namespace

TEST_P(CollidingSpheres, ConserveMomentumExchangeEnergyAndSeparate) {
  SolverConfig cfg;
  cfg.shape = std::get<0>(GetParam());
  cfg.transfer = std::get<1>(GetParam());
  cfg.cell_size = 0.05;  // 20 cells across the unit box, 2 points per cell
  std::vector<MaterialPtr> mat{std::make_shared<LinearElastic>(1000.0, 1000.0, 0.3)};
  ParticleStore s = two_spheres(0.025);
  const double mv = [&] {
    double a = 0;
    for (std::size_t p = 0; p < s.size(); ++p) a += s.col(Field::mass)[p] * std::sqrt(0.03);
    return a;
  }();
  Simulation sim(cfg, std::move(s), mat, 2);
  const double ke0 = sim.energy().kinetic;
  double ke_min = ke0, worst_error = 0.0, max_error = -1.0;
  while (sim.time() < 4.0) {
    sim.advance_to(std::min(4.0, sim.time() + 0.05));
    ke_min = std::min(ke_min, sim.energy().kinetic);
    worst_error = std::max(worst_error, std::abs(sim.energy().error()));
    max_error = std::max(max_error, sim.energy().error());
    // Momentum: no boundary and no body force, so it is conserved up to round-off in
    // sum(grad N) = 0 and sum(N) = 1; 1e-12 of sum m|v| allows ~1e4 ulps of accumulated error.
    ASSERT_LT(test::momentum(sim.particles()).norm(), 1e-12 * mv) << "t = " << sim.time();
  }
  // During contact most of the kinetic energy becomes strain energy (Sulsky et al. Fig. 5 shows
  // it dropping to about 10-20%); a missing internal force would keep it at 100%.
  EXPECT_LT(ke_min, 0.5 * ke0);
  // After the collision the spheres have rebounded: the centres move apart again and are
  // further apart than the 0.4 contact distance.
  const Vector3d gap = body_centre(sim.particles(), 1) - body_centre(sim.particles(), 0);
  EXPECT_GT(gap.norm(), 0.45);
  const double vsep = [&] {
    const auto& P = sim.particles();
    Vector3d v0 = Vector3d::Zero(), v1 = Vector3d::Zero();
    for (std::size_t p = 0; p < P.size(); ++p) {
      const Vector3d v(P.col(Field::vx)[p], P.col(Field::vy)[p], P.col(Field::vz)[p]);
      (P.col(IField::body)[p] == 0 ? v0 : v1) += v;
    }
    return (v1 - v0).dot(gap);
  }();
  EXPECT_GT(vsep, 0.0);
  // Total energy: MUSL with the time-centred kinetic energy keeps the error at a few percent
  // for this coarse contact (Sulsky's 2D runs lose ~5% through the no-slip contact); 10% bounds
  // the drift while a missing energy term or sign (100% errors) fails. APIC smooths the velocity
  // jump across the no-slip contact into the grid and so dissipates: measured losses of 21%
  // (ugimp) and 34% (bspline2) by t = 4, on 8 points across a sphere. It must never create
  // energy (a wrong sign in the affine term does), and the loss stays below 40%.
  if (cfg.transfer == TransferKind::flip) {
    EXPECT_LT(worst_error, 0.10);
  } else {
    EXPECT_LT(max_error, 1e-3);
    EXPECT_LT(worst_error, 0.40);
  }
  RecordProperty("worst_energy_error", std::to_string(worst_error));
  RecordProperty("min_kinetic_fraction", std::to_string(ke_min / ke0));
}

INSTANTIATE_TEST_SUITE_P(AllShapesAndTransfers, CollidingSpheres,
                         ::testing::Values(std::tuple{ShapeKind::linear, TransferKind::flip},
                                           std::tuple{ShapeKind::ugimp, TransferKind::flip},
                                           std::tuple{ShapeKind::bspline2, TransferKind::flip},
                                           std::tuple{ShapeKind::ugimp, TransferKind::apic},
                                           std::tuple{ShapeKind::bspline2, TransferKind::apic}),
                         [](const auto& param_info) {
                           return std::string(name_of(std::get<0>(param_info.param))) + "_" +
                                  std::string(name_of(std::get<1>(param_info.param)));
                         });
