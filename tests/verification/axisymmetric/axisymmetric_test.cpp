// The axisymmetric (r-z) mode of the MPM engine (issue 31; docs/validation-axisymmetric.md):
// kinematics near the axis, rigid motion, momentum, thread-count determinism and the engine's
// refusals. The spherical wave against its exact solution is in spherical_wave_rz_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

#include "rz_lattice.hpp"
#include "shatter/material/linear_elastic.hpp"
#include "shatter/mpm/simulation.hpp"
#include "support/same_state.hpp"

using namespace shatter;
using Eigen::Vector3d;

namespace {

constexpr double kRho = 2700.0, kYoung = 53.1e9, kPoisson = 0.15;  // the lab target's basalt

MaterialPtr basalt() {
  return std::make_shared<LinearElastic>(kRho, kYoung, kPoisson);
}

// A solid cylinder r < R, 0 < z < L at 2 x 2 points per cell, with velocity v(r, z).
ParticleStore cylinder(double h, double R, double L,
                       const std::function<Vector3d(double, double)>& v) {
  ParticleStore s;
  test::rz::add_rz(
      s, 0, R, 0.0, L, h / 2, kRho, [](double, double) { return true; }, v);
  return s;
}

// Head-on: a sphere of radius a at z = 3a moving at -V along z into a cylinder r < 4a, z < 2a.
ParticleStore head_on(double h, double a, double V) {
  ParticleStore s;
  test::rz::add_rz(
      s, 0, 4 * a, 0.0, 2 * a, h / 2, kRho, [](double, double) { return true; },
      [](double, double) { return Vector3d::Zero(); }, 0);
  test::rz::add_rz(
      s, 0, a, 2.0 * a + 0.5 * h, 4.0 * a + 0.5 * h, h / 2, kRho,
      [&](double r, double z) {
        return r * r + (z - 3 * a - 0.5 * h) * (z - 3 * a - 0.5 * h) <= a * a;
      },
      [&](double, double) { return Vector3d(0, 0, -V); }, 1);
  return s;
}

double z_momentum(const ParticleStore& P) {
  double sum = 0.0;
  for (std::size_t p = 0; p < P.size(); ++p) sum += P.col(Field::mass)[p] * P.col(Field::vz)[p];
  return sum;
}

}  // namespace

// A body moving along the axis as a rigid body: every nodal velocity is the mass-weighted mean of
// one value, so it is that value to round-off; no strain, no stress, no hoop force. Tolerance
// 1e-12 relative: a few ulps of the node sums, accumulated over 40 steps.
TEST(Axisymmetric, RigidTranslationAlongZIsExact) {
  const double h = 0.01, V = 3.0;
  Simulation sim(test::rz::config(h),
                 cylinder(h, 0.1, 0.05, [&](double, double) { return Vector3d(0, 0, V); }),
                 {basalt()}, 1);
  const ParticleStore start = sim.particles();
  for (int k = 0; k < 40; ++k) sim.step();
  const ParticleStore& P = sim.particles();
  const double t = sim.clock().time;
  ASSERT_GT(t, 0.0);
  for (std::size_t p = 0; p < P.size(); ++p) {
    EXPECT_NEAR(P.col(Field::vz)[p], V, 1e-12 * V);
    EXPECT_NEAR(P.col(Field::vx)[p], 0.0, 1e-12 * V);
    EXPECT_EQ(P.col(Field::y)[p], 0.0);
    EXPECT_EQ(P.col(Field::vy)[p], 0.0);
  }
  // Positions follow z0 + V t (the particles were re-ordered: compare by id).
  for (std::size_t p = 0; p < P.size(); ++p) {
    const auto id = static_cast<std::size_t>(P.col(IField::id)[p]);
    ASSERT_EQ(start.col(IField::id)[id], static_cast<std::int64_t>(id));
    EXPECT_NEAR(P.col(Field::z)[p], start.col(Field::z)[id] + V * t, 1e-12);
    EXPECT_NEAR(P.col(Field::x)[p], start.col(Field::x)[id], 1e-12);
  }
}

// A uniform radial expansion v = a (r, 0, 0) between two slip planes z = 0 and z = L: the exact
// strain rates are L_rr = L_thetatheta = a everywhere, so after one step sigma_rr =
// sigma_thetatheta = 2 (lambda + G) a dt. The hoop rate v_r / r must stay finite at the axis and
// equal the radial rate there (regularity: v_r is odd in r, so v_r / r -> dv_r/dr). What the
// r-weighted lumped-mass projection gives away (docs/validation-axisymmetric.md, "Axis"): the
// nodal velocity is sum m_p N v_p / sum m_p N with m_p ~ r_p, which overshoots a r_I by
// a var / r_I (var = sum N d^2 / sum N, the stencil's second moment: 0.19 h^2 for the linear hat
// at 2 points per cell, 1/4 h^2 for the quadratic B-spline): 19 % and 25 % at the first node off
// the axis, a quarter of that at the second, below 1 % beyond 5 cells (measured: linear 0.1875
// near the axis, 0.0034 beyond 6 cells; B-spline 0.238 and 0.0045).
TEST(Axisymmetric, UniformRadialExpansionIsRegularAtTheAxis) {
  for (const ShapeKind shape : {ShapeKind::linear, ShapeKind::bspline2}) {
    const double h = 0.01, R = 0.2, L = 0.04, a = 10.0;
    SolverConfig cfg = test::rz::config(h, shape);
    cfg.domain.lo.z() = 0.0;
    cfg.domain.hi.z() = L;
    cfg.domain.faces[4] = cfg.domain.faces[5] = BoundaryKind::slip;
    Simulation sim(cfg, cylinder(h, R, L, [&](double r, double) { return Vector3d(a * r, 0, 0); }),
                   {basalt()}, 1);
    const double dt = sim.clock().dt;
    sim.step();
    const ParticleStore& P = sim.particles();
    const auto model = basalt();  // held: the cast below must not outlive the model
    const auto* el = dynamic_cast<const LinearElastic*>(model.get());
    const double G = el->shear_modulus(), lambda = el->bulk_modulus() - 2.0 * G / 3.0;
    const double exact = 2.0 * (lambda + G) * a * dt;
    double worst_axis = 0.0, worst_interior = 0.0, worst_ratio = 0.0;
    for (std::size_t p = 0; p < P.size(); ++p) {
      const double r = P.col(Field::x)[p];
      const double srr = P.col(Field::sxx)[p], stt = P.col(Field::syy)[p];
      ASSERT_TRUE(std::isfinite(srr) && std::isfinite(stt)) << "r = " << r;
      if (r > R - 3 * h) continue;  // the free surface's release wave
      const double err = std::abs(stt / exact - 1.0);
      if (r < 2 * h) {
        worst_axis = std::max(worst_axis, err);
        worst_ratio = std::max(worst_ratio, std::abs(stt / srr - 1.0));
      } else if (r > 6 * h) {
        worst_interior = std::max(worst_interior, err);
      }
    }
    std::cout << name_of(shape) << ": hoop stress error near the axis " << worst_axis
              << ", hoop/radial - 1 there " << worst_ratio << ", beyond 6 cells " << worst_interior
              << "\n";
    // Bounds: the projection's overshoot above (0.19 and 0.25 at the first node), then its
    // 1/r_I^2 decay (0.005-0.007 at 6 cells). A singular hoop term (v_r / r with v_r not odd
    // at the axis) would blow the first bound up; a missing hoop rate, the third.
    EXPECT_LT(worst_axis, 0.25);
    EXPECT_LT(worst_ratio, 0.25);
    EXPECT_LT(worst_interior, 0.01);
  }
}

// Head-on impact at 100 m/s: the axis and the free faces exert no force along z, so the total
// momentum along z is conserved to round-off (the internal forces sum to zero node by node
// because the shapes are a partition of unity, and the hoop force is radial). Tolerance 1e-12
// relative over 150 steps.
TEST(Axisymmetric, MomentumAlongZIsConserved) {
  const double h = 0.005, a = 0.02, V = 100.0;
  Simulation sim(test::rz::config(h), head_on(h, a, V), {basalt()}, 1);
  const double p0 = z_momentum(sim.particles());
  for (int k = 0; k < 150; ++k) sim.step();
  const double p1 = z_momentum(sim.particles());
  EXPECT_NEAR(p1, p0, 1e-12 * std::abs(p0));
  // The bodies met: the target moves.
  double target = 0.0;
  const ParticleStore& P = sim.particles();
  for (std::size_t p = 0; p < P.size(); ++p) {
    if (P.col(IField::body)[p] == 0) target += P.col(Field::mass)[p] * P.col(Field::vz)[p];
  }
  EXPECT_LT(target, -0.05 * std::abs(p0));
}

// The r-z step with 1 and 2 threads: bitwise the same state (the engine's colouring and exact
// sums, unchanged by the hoop terms).
TEST(Axisymmetric, OneAndTwoThreadsGiveBitwiseIdenticalState) {
  for (const ShapeKind shape : {ShapeKind::linear, ShapeKind::bspline2}) {
    const double h = 0.005, a = 0.02, V = 100.0;
    auto run = [&](int threads) {
      auto sim = std::make_unique<Simulation>(test::rz::config(h, shape), head_on(h, a, V),
                                              std::vector<MaterialPtr>{basalt()}, threads);
      for (int k = 0; k < 60; ++k) sim->step();
      return sim;
    };
    const auto one = run(1), two = run(2);
    EXPECT_EQ(one->clock().time, two->clock().time);
    EXPECT_EQ(one->energy().kinetic, two->energy().kinetic);
    EXPECT_EQ(one->energy().internal, two->energy().internal);
    test::expect_bitwise_equal_columns(one->particles(), two->particles());
  }
}

// What the r-z engine does not carry is refused before the first step, naming the key.
TEST(Axisymmetric, UnsupportedCombinationsAreRefused) {
  const double h = 0.01;
  const auto still = [](double, double) { return Vector3d::Zero(); };
  const auto refused = [&](SolverConfig cfg, ParticleStore s, const std::string& key) {
    try {
      Simulation sim(cfg, std::move(s), {basalt()}, 1);
      ADD_FAILURE() << "not refused: " << key;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  };
  SolverConfig c = test::rz::config(h, ShapeKind::ugimp);
  refused(c, cylinder(h, 0.05, 0.05, still), "solver.shape");
  c = test::rz::config(h);
  c.transfer = TransferKind::apic;
  refused(c, cylinder(h, 0.05, 0.05, still), "solver.transfer");
  c = test::rz::config(h);
  c.contact.kind = ContactKind::multi_field;
  refused(c, cylinder(h, 0.05, 0.05, still), "solver.contact");
  c = test::rz::config(h);
  c.gravity = Vector3d(9.81, 0, 0);
  refused(c, cylinder(h, 0.05, 0.05, still), "solver.gravity");
  c = test::rz::config(h);
  c.domain.faces[0] = BoundaryKind::none;
  refused(c, cylinder(h, 0.05, 0.05, still), "x_lo");
  // A point off the half-plane (a 3-D body handed to the r-z engine).
  ParticleStore off = cylinder(h, 0.05, 0.05, still);
  off.col(Field::y)[3] = 0.001;
  refused(test::rz::config(h), std::move(off), "y = 0");
}
