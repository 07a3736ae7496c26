// A planar symmetric impact in r-z (issue 31, "a planar impact in r-z against the exact solutions
// the 3-D tests use"): two aluminium cylinders r < R, each 0.2 m long, at +-u0 along the axis, the
// wall r = R a slip face. Uniaxial strain along z, so the exact solution is the 3-D planar
// impact's (tests/verification/shock_tube_planar_impact_test.cpp): the material between the two
// outgoing shocks rests at the pressure of the principal Hugoniot at up = u0, and the fronts run
// at Us - up (both from the material probe). In r-z the hydrostatic plateau exercises the hoop
// terms: sigma_thetatheta = sigma_rr = -P, so the radial divergence of the stress must balance the
// hoop force -sigma_thetatheta V N / r node by node, or the material would move radially.
// The wall is a mirror (BoundaryKind::symmetry, a frictionless rigid wall whose ghost nodes are
// folded back): with a plain slip face the quadratic B-spline's stencil is cut at the wall, and
// the points within a cell of it carried a pressure 14% high and radial speeds up to 0.1 u0
// (measured, 4 and 2 mm); the 3-D test sidesteps that with a one-cell-thick slab.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "rz_lattice.hpp"
#include "shatter/material/catalogue.hpp"
#include "shatter/material/probe.hpp"
#include "shatter/mpm/simulation.hpp"

using namespace shatter;
using Eigen::Vector3d;

namespace {

constexpr double kRho = 2703.0, kU0 = 500.0, kLength = 0.2, kRadius = 0.02;

struct PlanarResult {
  double pressure = 0.0;     // mean over the plateau
  double rest = 0.0;         // mean |v_z| over the plateau
  double radial = 0.0;       // mean |v_r| over the plateau
  double radial_max = 0.0;   // largest |v_r| anywhere
  double front_speed = 0.0;  // from two times
  double l1_vz = 0.0;        // L1 error of v_z(z) against the exact profile, over u0 * 2 L
  double energy_error = 0.0;
};

PlanarResult run(double h, ShapeKind shape, const HugoniotRow& hug) {
  const auto spec = MaterialCatalogue::builtin().get("aluminium_6061");
  ParticleStore s;
  const auto all = [](double, double) { return true; };
  test::rz::add_rz(s, 0, kRadius, -kLength, 0.0, h / 2, kRho, all,
                   [](double, double) { return Vector3d(0, 0, kU0); });
  test::rz::add_rz(s, 0, kRadius, 0.0, kLength, h / 2, kRho, all,
                   [](double, double) { return Vector3d(0, 0, -kU0); });
  SolverConfig cfg = test::rz::config(h, shape);
  cfg.domain.hi.x() = kRadius;
  cfg.domain.faces[1] = BoundaryKind::symmetry;  // the wall r = R: uniaxial strain
  cfg.domain.lo.z() = -2 * kLength;
  cfg.domain.hi.z() = 2 * kLength;
  cfg.viscosity = {0.5, 1.5};  // as the 3-D test
  Simulation sim(cfg, std::move(s), {make_material(spec)}, 1);

  const double front_speed = hug.us - hug.up;  // in the frame of the resting material
  const auto front = [&] {
    double z_front = 0.0;  // the farthest point compressed past half the jump's density
    const double half_rho = 0.5 * (kRho + hug.rho);
    const auto& P = sim.particles();
    for (std::size_t p = 0; p < P.size(); ++p)
      if (P.col(Field::rho)[p] > half_rho) z_front = std::max(z_front, P.col(Field::z)[p]);
    return z_front;
  };
  const double t1 = 10e-6, t2 = 25e-6;
  sim.advance_to(t1);
  const double z1 = front();
  sim.advance_to(t2);
  const double z2 = front();

  PlanarResult r;
  r.front_speed = (z2 - z1) / (t2 - t1);
  const auto& P = sim.particles();
  const double zf = front_speed * sim.clock().time;  // exact front position
  double psum = 0, vsum = 0, rsum = 0, l1 = 0, msum = 0;
  int n = 0;
  for (std::size_t p = 0; p < P.size(); ++p) {
    const double z = P.col(Field::z)[p], vz = P.col(Field::vz)[p];
    r.radial_max = std::max(r.radial_max, std::abs(P.col(Field::vx)[p]));
    // v_z of the exact solution: 0 between the fronts, the incoming speed outside.
    const double exact = std::abs(z) < zf ? 0.0 : (z < 0 ? kU0 : -kU0);
    const double m = P.col(Field::mass)[p];
    l1 += m * std::abs(vz - exact);
    msum += m;
    if (std::abs(z) > 3 * h && std::abs(z) < z2 - 3 * h) {  // the 3-D test's plateau
      psum += P.col(Field::pressure)[p];
      vsum += std::abs(vz);
      rsum += std::abs(P.col(Field::vx)[p]);
      ++n;
    }
  }
  EXPECT_GT(n, 100);
  r.pressure = psum / std::max(n, 1);
  r.rest = vsum / std::max(n, 1);
  r.radial = rsum / std::max(n, 1);
  r.l1_vz = l1 / msum / kU0;  // mass-weighted mean |error| over u0
  r.energy_error = sim.energy().error();
  return r;
}

void print(const char* name, double h, const PlanarResult& r, const HugoniotRow& hug) {
  std::printf(
      "planar impact r-z, %s, h = %.0f mm: p %.4g Pa (Hugoniot %.4g, %+.2f%%), front %.1f m/s "
      "(Us - up %.1f), |v_z| at rest %.3g m/s, |v_r| mean %.3g max %.3g m/s, L1(v_z)/u0 %.4f, "
      "energy error %.2e\n",
      name, h * 1e3, r.pressure, hug.p, 100 * (r.pressure / hug.p - 1), r.front_speed,
      hug.us - hug.up, r.rest, r.radial, r.radial_max, r.l1_vz, r.energy_error);
}

// The bounds shared by both shapes, from the 3-D test (tests/verification/
// shock_tube_planar_impact_test.cpp) and its reasons: 3% on the ~8 GPa plateau (viscous smearing,
// transfer noise), at rest within 3% of u0, the front (located to ~h/2 at two times) within 4%;
// kinetic + internal energy conserved within 1% (the viscous shock turns 3/4 of the kinetic
// energy into heat: an energy update out of step with the work shows at the 10% level).
void expect_planar_state(const PlanarResult& r, const HugoniotRow& hug) {
  EXPECT_NEAR(r.pressure, hug.p, 0.03 * hug.p);
  EXPECT_LT(r.rest, 0.03 * kU0);
  EXPECT_NEAR(r.front_speed, hug.us - hug.up, 0.04 * (hug.us - hug.up));
  EXPECT_LT(std::abs(r.energy_error), 0.01);
}

HugoniotRow aluminium_jump() {
  const auto spec = MaterialCatalogue::builtin().get("aluminium_6061");
  const double up[] = {kU0};
  return hugoniot(spec, up).front();
}

}  // namespace

// Measured (Release): B-spline 4 / 2 mm: p -1.09% / -0.73%, |v_z| at rest 7.8 / 3.8 m/s, mean
// |v_r| over the plateau 1.3 / 1.7 m/s (the largest 7.8 / 15.7 m/s, in the front's transient),
// L1(v_z)/u0 0.065 / 0.036 (order 0.87), energy error 1e-4 / 5e-5.
TEST(PlanarImpactRz, BsplineMatchesTheHugoniotAndConverges) {
  const HugoniotRow hug = aluminium_jump();
  const double hs[] = {4e-3, 2e-3};
  PlanarResult res[2];
  for (int k = 0; k < 2; ++k) {
    res[k] = run(hs[k], ShapeKind::bspline2, hug);
    print("B-spline", hs[k], res[k], hug);
    expect_planar_state(res[k], hug);
    // Radial equilibrium: the plateau does not move outward or inward. A missing or doubled hoop
    // force drives it at ~P / (rho c) ~ 0.2 u0; the B-spline's two-point quadrature of the
    // r-weighted force leaves a residual (1.3-1.7 m/s measured), bound 1% of u0.
    EXPECT_LT(res[k].radial, 0.01 * kU0);
  }
  // The v_z profile is a step smeared over a few cells: its L1 error falls as h (order 1 for a
  // shock in a first-order viscous scheme). 0.6 leaves room for the two resolutions' noise; a
  // front that lags by a fixed distance, or a smearing that does not shrink with h, gives ~0.
  const double order = std::log2(res[0].l1_vz / res[1].l1_vz);
  std::printf("planar impact r-z, B-spline: L1(v_z) order %.2f\n", order);
  EXPECT_GT(order, 0.6);
}

// With the linear hat the radial balance is exact: for a uniform stress the radial force on node
// I is P sum_p 2 pi A d(r N_I)/dr at the points, and the two points per cell integrate that linear
// function exactly, to [r N_I] = 0 at every interior node (and at the axis, where r = 0; the wall
// node is held by the mirror). So v_r stays 0 to round-off (measured 1e-11 m/s), a strict check
// that the hoop force and the hoop rate are the r-weighted forms of one another. Measured: p
// -2.30%, front -1.3%, energy error -4.9e-3 at 2 mm.
TEST(PlanarImpactRz, LinearHatKeepsRadialEquilibriumExactly) {
  const HugoniotRow hug = aluminium_jump();
  const PlanarResult r = run(2e-3, ShapeKind::linear, hug);
  print("linear", 2e-3, r, hug);
  expect_planar_state(r, hug);
  EXPECT_LT(r.radial_max, 1e-9 * kU0);
}
