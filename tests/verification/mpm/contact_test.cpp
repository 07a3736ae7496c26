// Multi-velocity-field contact between bodies (issue 11 item 3; Bardenhagen et al. 2000, 2001):
// Coulomb sliding against the analytic deceleration mu g, a rebound without tension across the
// interface, no interpenetration, momentum to round-off, and a scene of one body that does not
// change at all with the option on.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "shatter/material/linear_elastic.hpp"
#include "shatter/mpm/simulation.hpp"
#include "support/lattice.hpp"
#include "support/same_state.hpp"

using namespace shatter;
using Eigen::Vector3d;

namespace {

constexpr double kRho = 1000.0;

std::string sci(double v) {
  std::ostringstream o;
  o << std::scientific << v;
  return o.str();
}

MaterialPtr elastic(double young) {
  return std::make_shared<LinearElastic>(kRho, young, 0.25);
}

// Mass-weighted mean of a velocity component (or momentum, with `momentum`) of one body.
double body_mean(const ParticleStore& P, int body, Field f, bool momentum = false) {
  double s = 0.0, m = 0.0;
  for (std::size_t p = 0; p < P.size(); ++p) {
    if (P.col(IField::body)[p] != body) continue;
    s += P.col(Field::mass)[p] * P.col(f)[p];
    m += P.col(Field::mass)[p];
  }
  return momentum ? s : s / m;
}

double body_extreme(const ParticleStore& P, int body, Field f, bool highest) {
  double e = highest ? -1e300 : 1e300;
  for (std::size_t p = 0; p < P.size(); ++p) {
    if (P.col(IField::body)[p] != body) continue;
    e = highest ? std::max(e, P.col(f)[p]) : std::min(e, P.col(f)[p]);
  }
  return e;
}

// A 0.1 m block (body 1) slides at 1 m/s on a 0.4 m slab (body 0) that rests on a fixed floor,
// under gravity; y faces slip (a slice of a wide block). Returns the upper block's mean vx
// sampled every 5 ms.
struct Slide {
  std::vector<double> t, vx;
};
Slide slide(double mu, ContactKind kind) {
  ParticleStore s;
  const double h = 0.02, sp = 0.01;
  test::add_box(s, 0, Vector3d(0.0, 0.0, 0.0), Vector3d(0.4, 0.04, 0.04), sp, kRho,
                Vector3d::Zero(), 0);
  test::add_box(s, 0, Vector3d(0.05, 0.0, 0.04), Vector3d(0.15, 0.04, 0.08), sp, kRho,
                Vector3d(1.0, 0.0, 0.0), 1);
  SolverConfig cfg;
  cfg.cell_size = h;
  cfg.gravity = Vector3d(0, 0, -9.81);
  cfg.domain.lo = Vector3d(-0.2, 0.0, 0.0);
  cfg.domain.hi = Vector3d(0.8, 0.04, 0.4);
  cfg.domain.faces = {BoundaryKind::none, BoundaryKind::none,  BoundaryKind::slip,
                      BoundaryKind::slip, BoundaryKind::fixed, BoundaryKind::none};
  cfg.contact.kind = kind;
  // The pair's coefficient must override the scene-wide one (0.7 would stop the block by 0.15 s).
  cfg.contact.friction = 0.7;
  cfg.contact.pairs = {{1, 0, mu}};
  // E = 2.5e6 Pa: c = 50 m/s, 50x the sliding speed; the static sag rho g H / E ~ 2e-4 is nil.
  Simulation sim(cfg, std::move(s), {elastic(2.5e6)}, 2);
  Slide out;
  for (double t = 0.0; t <= 0.12 + 1e-12; t += 0.005) {
    sim.advance_to(t);
    out.t.push_back(sim.time());
    out.vx.push_back(body_mean(sim.particles(), 1, Field::vx));
  }
  return out;
}

// Least-squares slope of vx(t) over t >= t0.
double slope(const Slide& s, double t0) {
  double n = 0, st = 0, sv = 0, stt = 0, stv = 0;
  for (std::size_t k = 0; k < s.t.size(); ++k) {
    if (s.t[k] < t0) continue;
    n += 1;
    st += s.t[k];
    sv += s.vx[k];
    stt += s.t[k] * s.t[k];
    stv += s.t[k] * s.vx[k];
  }
  return (n * stv - st * sv) / (n * stt - st * st);
}

}  // namespace

TEST(Contact, BlockSlidingOnABlockDeceleratesAtMuG) {
  // Coulomb sliding: a = -mu g while the block slides (it stops at v0 / (mu g) = 0.34 s, after
  // the window, which ends at 0.12 s). The fit starts at 20 ms, after the first ~10 oscillations of
  // the normal force (the block starts unstressed and settles onto the slab: period 4 H / c = 3.2
  // ms). Tolerance 10% of mu g. Measured 1.002 mu g (1.004 with the one-pass correction); the
  // grid's normal force still rings around m g, the nodes under the block's end faces carry tilted
  // normals, and the block is 2 cells thick (with the remapped strain rate at contact nodes, since
  // replaced, it was 1.036).
  const double mu = 0.3, g = 9.81;
  const Slide s = slide(mu, ContactKind::multi_field);
  const double a = slope(s, 0.02);
  RecordProperty("deceleration_over_mu_g", std::to_string(-a / (mu * g)));
  EXPECT_NEAR(-a, mu * g, 0.10 * mu * g);
  // Frictionless: the block keeps its speed (|a| below 2% of the mu = 0.3 deceleration).
  const Slide free = slide(0.0, ContactKind::multi_field);
  const double a0 = slope(free, 0.02);
  RecordProperty("frictionless_deceleration", sci(a0));
  EXPECT_LT(std::abs(a0), 0.02 * mu * g);
  EXPECT_GT(free.vx.back(), 0.98);
}

namespace {

struct Bounce {
  double pz_drop = 0.0;    // largest step-to-step decrease of the sphere's z momentum
  double pz_final = 0.0;   // sphere's z momentum at the end
  double pz0 = 0.0;        // ... at the start (< 0: moving down)
  double min_gap = 1e300;  // lowest sphere point minus highest plate point
  double final_gap = 0.0;
  double momentum_error = 0.0;  // |P(t) - P(0)| / sum m|v|, worst
  std::unique_ptr<Simulation> sim;
};

// An elastic sphere (body 0) hits a free slab (body 1) at 1 m/s with a tangential 0.5 m/s; no
// gravity, no boundaries.
Bounce bounce(ContactKind kind, double mu, int threads = 2,
              TransferKind transfer = TransferKind::flip) {
  ParticleStore s;
  const double sp = 0.02;
  test::add_box(s, 0, Vector3d(0.0, 0.0, 0.0), Vector3d(0.32, 0.32, 0.08), sp, kRho,
                Vector3d::Zero(), 1);
  test::add_sphere(s, 0, Vector3d(0.16, 0.16, 0.08 + 0.1 + 0.03), 0.1, sp, kRho,
                   Vector3d(0.5, 0.0, -1.0), 0);
  SolverConfig cfg;
  cfg.cell_size = 0.04;
  cfg.transfer = transfer;
  cfg.contact.kind = kind;
  cfg.contact.friction = mu;
  Bounce b;
  const Vector3d p0 = test::momentum(s);
  double mv = 0.0;
  for (std::size_t p = 0; p < s.size(); ++p) {
    mv += s.col(Field::mass)[p] * std::hypot(s.col(Field::vx)[p], s.col(Field::vz)[p]);
  }
  b.sim = std::make_unique<Simulation>(cfg, std::move(s), std::vector<MaterialPtr>{elastic(1e7)},
                                       threads);
  Simulation& sim = *b.sim;
  double last = body_mean(sim.particles(), 0, Field::vz, true);
  b.pz0 = last;
  while (sim.time() < 0.1) {
    sim.step();
    const ParticleStore& P = sim.particles();
    const double pz = body_mean(P, 0, Field::vz, true);
    b.pz_drop = std::max(b.pz_drop, last - pz);
    last = pz;
    const double gap = body_extreme(P, 0, Field::z, false) - body_extreme(P, 1, Field::z, true);
    b.min_gap = std::min(b.min_gap, gap);
    b.final_gap = gap;
    b.momentum_error = std::max(b.momentum_error, (test::momentum(P) - p0).norm() / mv);
  }
  b.pz_final = last;
  return b;
}

}  // namespace

TEST(Contact, SphereBouncesOffAPlateWithoutStickingOrInterpenetrating) {
  // Frictionless, so that every force the plate exerts on the sphere lies along a contact normal.
  const Bounce b = bounce(ContactKind::multi_field, 0.0);
  // Only compression crosses the interface: the plate can only push the sphere up, so the
  // sphere's z momentum never decreases. Tolerance 1e-9 of its initial momentum: the momentum
  // round-off of this scene (below; measured drop 3.5e-11); the single field's pull is 1.7e-2.
  EXPECT_LT(b.pz_drop, 1e-9 * std::abs(b.pz0));
  // It rebounded and flies away: measured 0.082 of the approach momentum comes back (0.076
  // with the one-pass correction; plate 2x the sphere's mass and 2 cells thick, so much of the
  // energy stays in its vibration; the head-on spheres below measure restitution). 0.03 rejects
  // a sphere that stays on the plate.
  EXPECT_GT(b.pz_final, 0.03 * std::abs(b.pz0));
  EXPECT_GT(b.final_gap, 0.03);
  // No interpenetration: the lowest sphere point stays above the highest plate point (points
  // start one spacing apart across the 0.03 m gap: 0.03 + 0.02).
  EXPECT_GT(b.min_gap, 0.0);
  // Momentum: the corrections are equal and opposite. Bound 1e-9 of sum m|v|: the same scene
  // with the single shared field drifts 9.7e-11 over its ~1100 steps (round-off of the nodal
  // sums; nodes lighter than the empty-node threshold drop their force), and contact may not
  // add more than that order (measured 1.2e-10; with friction: HeadOnCubes below).
  EXPECT_LT(b.momentum_error, 1e-9);
  // Energy: contact may only take energy out (measured -0.285 of the largest K + U, -0.29 with
  // the one-pass correction: see TwoElasticSpheresHeadOn). Bound +1%: the free bodies' leapfrog
  // error is < 1e-3; the remapped strain rate at contact nodes (before USL there) made it +0.31.
  EXPECT_LT(b.sim->energy().error(), 0.01);
  RecordProperty("min_gap_m", std::to_string(b.min_gap));
  RecordProperty("rebound_ratio", std::to_string(b.pz_final / std::abs(b.pz0)));
  RecordProperty("momentum_error", sci(b.momentum_error));
  RecordProperty("tension_drop", sci(b.pz_drop / std::abs(b.pz0)));
  RecordProperty("energy_error", sci(b.sim->energy().error()));
  // The same impact with the paper's single shared field: the plate pulls the sphere back as it
  // leaves (tension across the interface), which the check above would catch.
  const Bounce glued = bounce(ContactKind::single_field, 0.0);
  EXPECT_GT(glued.pz_drop, 1e-3 * std::abs(glued.pz0));
  RecordProperty("single_field_pull", std::to_string(glued.pz_drop / std::abs(glued.pz0)));
}

TEST(Contact, OneBodyCostsNothingAndChangesNothing) {
  // With one body the multi-field option must give the single-field step bitwise.
  auto run = [](ContactKind kind) {
    ParticleStore s;
    test::add_sphere(s, 0, Vector3d(0.2, 0.2, 0.2), 0.2, 0.025, kRho, Vector3d(1, 0.5, -1), 0);
    SolverConfig cfg;
    cfg.cell_size = 0.05;
    cfg.gravity = Vector3d(0, 0, -9.81);
    cfg.domain.lo.z() = -0.05;
    cfg.domain.faces[4] = BoundaryKind::fixed;
    cfg.contact.kind = kind;
    cfg.contact.friction = 0.5;
    auto sim =
        std::make_unique<Simulation>(cfg, std::move(s), std::vector<MaterialPtr>{elastic(1e5)}, 2);
    for (int k = 0; k < 60; ++k) sim->step();
    return sim;
  };
  const auto a = run(ContactKind::single_field);
  const auto b = run(ContactKind::multi_field);
  EXPECT_EQ(a->grid_bytes(), b->grid_bytes());
  EXPECT_EQ(a->energy().error(), b->energy().error());
  test::expect_bitwise_equal_columns(a->particles(), b->particles());
}

TEST(Contact, InvalidSettingsAreRejected) {
  ParticleStore s;
  test::add_box(s, 0, Vector3d::Zero(), Vector3d::Constant(0.1), 0.05, kRho, Vector3d::Zero(), 0);
  SolverConfig cfg;
  cfg.cell_size = 0.1;
  cfg.contact.kind = ContactKind::multi_field;
  cfg.contact.friction = -0.1;
  EXPECT_THROW(Simulation(cfg, s, {elastic(1e5)}), std::invalid_argument);
  cfg.contact.friction = 0.1;
  cfg.contact.pairs.push_back({1, 1, 0.2});
  EXPECT_THROW(Simulation(cfg, s, {elastic(1e5)}), std::invalid_argument);
}

// Two elastic cubes (0.16 m, E = 1e7 Pa) meet head-on at 1 m/s each, sliding past each other
// at 0.6 m/s with mu = 0.3. Contact does no work of its
// own: the total energy may only fall (the node pair's inelastic correction), never rise.
// Bound 1% of the initial energy (the leapfrog energy error of the free cubes is < 1e-3).
// With the contact correction applied to the remapped velocities as well (Simulation::remap says
// why it is not) this reached 2.2x (uGIMP, FLIP). Rebound: measured 0.73 (FLIP) and 0.67
// (APIC) of the approach speed (0.64 and 0.67 with the one-pass correction); 0.5 rejects
// sticking.
TEST(Contact, HeadOnCubesReboundWithoutGainingEnergy) {
  for (const TransferKind tr : {TransferKind::flip, TransferKind::apic}) {
    ParticleStore s;
    // A tangential 0.3 m/s each way, so that friction (mu = 0.3) acts too.
    test::add_box(s, 0, Vector3d(0, 0, 0), Vector3d(0.16, 0.16, 0.16), 0.02, kRho,
                  Vector3d(1, 0.3, 0), 0);
    test::add_box(s, 0, Vector3d(0.2, 0, 0), Vector3d(0.36, 0.16, 0.16), 0.02, kRho,
                  Vector3d(-1, -0.3, 0), 1);
    double mv = 0.0;
    for (std::size_t p = 0; p < s.size(); ++p) mv += s.col(Field::mass)[p] * std::hypot(1.0, 0.3);
    SolverConfig cfg;
    cfg.cell_size = 0.04;
    cfg.transfer = tr;
    cfg.contact.kind = ContactKind::multi_field;
    cfg.contact.friction = 0.3;
    Simulation sim(cfg, std::move(s), std::vector<MaterialPtr>{elastic(1e7)}, 2);
    const double e0 = sim.energy().kinetic;
    double emax = 0.0, momentum_error = 0.0;
    while (sim.time() < 0.03) {
      sim.step();
      emax = std::max(emax, sim.energy().kinetic + sim.energy().internal);
      momentum_error = std::max(momentum_error, test::momentum(sim.particles()).norm() / mv);
    }
    const double v0 = body_mean(sim.particles(), 0, Field::vx);
    const double v1 = body_mean(sim.particles(), 1, Field::vx);
    SCOPED_TRACE(std::string(name_of(tr)));
    EXPECT_LT(emax, 1.01 * e0);
    EXPECT_LT(v0, -0.5);  // body 0 came in at +1 m/s and goes back
    EXPECT_GT(v1, 0.5);
    EXPECT_NEAR(v0, -v1, 1e-9);  // equal and opposite (momentum)
    // Momentum with friction: 1e-9 of sum m|v|, as in the bounce (round-off of the nodal sums).
    EXPECT_LT(momentum_error, 1e-9);
    RecordProperty("rebound_" + std::string(name_of(tr)), std::to_string(-v0));
    RecordProperty("momentum_error_" + std::string(name_of(tr)), sci(momentum_error));
    // Friction slowed the tangential motion (each cube came in at 0.3 m/s).
    RecordProperty("tangential_" + std::string(name_of(tr)),
                   std::to_string(body_mean(sim.particles(), 0, Field::vy)));
  }
}

// Coefficient of restitution of a slow elastic impact: two equal elastic spheres (radius 0.1 m,
// 5 cells across, E = 1e7 Pa, c = 100 m/s) meet head-on at 1 m/s each (v/c = 0.01). Physically
// the impact is quasi-static (Hertz contact time 2.87 (m*^2 / (R* E*^2 v))^(1/5) = 12 ms against a
// 2 ms wave transit of a sphere), so e is near 1; the single shared field gives 0.991 here.
// Multi-field contact measures 0.757 (energy K + U 0.61 of its start): grid-node contact
// dissipates to first order in the cell size, because each body's field at a contact node is
// the average of its own points up to 1.5 cells inside it, so the two fields keep a relative
// normal velocity of the order of the strain rate times h that the correction removes every
// step; at 10 cells across 0.881 and 0.81 (docs/verification.md, "Contact between bodies"). The
// one-pass correction this replaced gave 0.668 and 0.46. Bounds: e > 0.70 and K + U > 0.55 E0
// reject the one-pass scheme; equal and opposite rebound to 1e-9 (momentum, as in HeadOnCubes).
TEST(Contact, TwoElasticSpheresHeadOn) {
  const double h = 0.04;
  ParticleStore s;
  test::add_sphere(s, 0, Vector3d(0.1, 0.1, 0.1), 0.1, h / 2, kRho, Vector3d(1, 0, 0), 0);
  test::add_sphere(s, 0, Vector3d(0.3 + h, 0.1, 0.1), 0.1, h / 2, kRho, Vector3d(-1, 0, 0), 1);
  SolverConfig cfg;
  cfg.cell_size = h;
  cfg.contact.kind = ContactKind::multi_field;
  Simulation sim(cfg, std::move(s), std::vector<MaterialPtr>{elastic(1e7)}, 2);
  const double e0 = sim.energy().kinetic;
  // The surfaces close at 2 m/s from h apart: contact from ~20 ms to ~33 ms.
  while (sim.time() < 0.04) sim.step();
  const double v0 = body_mean(sim.particles(), 0, Field::vx);
  const double v1 = body_mean(sim.particles(), 1, Field::vx);
  const double ku = (sim.energy().kinetic + sim.energy().internal) / e0;
  RecordProperty("restitution", std::to_string(-v0));
  RecordProperty("energy_left", std::to_string(ku));
  EXPECT_GT(-v0, 0.70);
  EXPECT_GT(ku, 0.55);
  EXPECT_LT(ku, 1.01);
  EXPECT_NEAR(v0, -v1, 1e-9);
}
