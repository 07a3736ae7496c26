// The unresolved kinetic energy (issue 16, EnergyBudget::unresolved_kinetic): the particles'
// kinetic energy sum_p m_p |v_p|^2/2 minus the grid's sum_I |p_I|^2/(2 m_I), p_I and m_I the
// lumped P2G momentum and mass of the same step. After the first step the P2G was made from the
// initial positions and velocities (v^{-1/2} = v^0), so it can be checked against the particle
// data set up here.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <tuple>

#include "mpm/shape.hpp"
#include "shatter/material/linear_elastic.hpp"
#include "shatter/mpm/simulation.hpp"
#include "support/lattice.hpp"

using namespace shatter;
using Eigen::Vector3d;

namespace {

constexpr double kRho = 1000.0, kH = 0.1;

std::vector<MaterialPtr> elastic() {
  return {std::make_shared<LinearElastic>(kRho, 1e7, 0.25)};
}

SolverConfig config(ShapeKind shape) {
  SolverConfig c;
  c.shape = shape;
  c.cell_size = kH;
  return c;
}

// Independent reference: the lumped P2G of the particle data on a dense map of nodes, with the
// shape function's own weights (node i at i h, xi = x / h, half size min(size0 / 2h, 1/2) as in
// kernels::store_stencils), in long double.
template <class Shape>
long double brute_force_unresolved(const ParticleStore& P) {
  std::map<std::array<int, 3>, std::array<long double, 4>> nodes;  // m, px, py, pz
  long double kinetic = 0.0L;
  const auto m = P.col(Field::mass), s = P.col(Field::size0);
  const std::span<const double> x[3] = {P.col(Field::x), P.col(Field::y), P.col(Field::z)};
  const std::span<const double> v[3] = {P.col(Field::vx), P.col(Field::vy), P.col(Field::vz)};
  for (std::size_t p = 0; p < P.size(); ++p) {
    const double lp = std::min(0.5 * s[p] / kH, 0.5);
    double w[3][Shape::kWidth], dw[Shape::kWidth];
    int first[3];
    for (int d = 0; d < 3; ++d) first[d] = Shape::weights(x[d][p] / kH, 1.0, lp, w[d], dw);
    for (int a = 0; a < Shape::kWidth; ++a) {
      for (int b = 0; b < Shape::kWidth; ++b) {
        for (int c = 0; c < Shape::kWidth; ++c) {
          const long double wn = static_cast<long double>(w[0][a]) * w[1][b] * w[2][c];
          auto& n = nodes[{first[0] + a, first[1] + b, first[2] + c}];
          n[0] += wn * m[p];
          for (int d = 0; d < 3; ++d) n[1 + d] += wn * m[p] * v[d][p];
        }
      }
    }
    kinetic += 0.5L * m[p] * (v[0][p] * v[0][p] + v[1][p] * v[1][p] + v[2][p] * v[2][p]);
  }
  long double resolved = 0.0L;
  for (const auto& [key, n] : nodes) {
    if (n[0] > 0.0L) resolved += 0.5L * (n[1] * n[1] + n[2] * n[2] + n[3] * n[3]) / n[0];
  }
  return kinetic - resolved;
}

class Unresolved : public ::testing::TestWithParam<ShapeKind> {};

}  // namespace

// A uniform velocity is reproduced exactly by the grid (partition of unity): nothing is
// unresolved. The node terms are each rounded, so the difference of two sums of order K is
// round-off of K: 1e-13 K leaves ~500 ulps for ~1000 node terms.
TEST_P(Unresolved, RigidTranslationHasNone) {
  ParticleStore s;
  const Vector3d v(3.0, -2.0, 1.0);
  test::add_box(s, 0, Vector3d(0.03, 0.0, -0.11), Vector3d(0.63, 0.4, 0.29), 0.05, kRho, v);
  Simulation sim(config(GetParam()), std::move(s), elastic(), 1);
  for (int k = 0; k < 20; ++k) {  // crosses cell faces: every step's P2G, not just the first
    sim.step();
    const EnergyBudget& e = sim.energy();
    ASSERT_GT(e.transferred_kinetic, 0.0);
    EXPECT_NEAR(e.unresolved_kinetic / e.transferred_kinetic, 0.0, 1e-13) << "step " << k;
  }
}

// 27 equal masses in one cell at 1/4, 1/2, 3/4 of it on each axis, with velocity
// s_i s_j s_k, s = (1, -2, 1): with linear shapes each node's momentum is a product of the
// per-axis sums sum_i s_i N(f_i), and (1 - f) and f both give 3/4 - 1 + 1/4 = 0 (and its
// mirror): the mode lies wholly in the null space of the P2G map, so p_I = 0 up to round-off and
// all of the kinetic energy is unresolved. The resolved part is (round-off)^2: 1e-13 relative.
TEST(UnresolvedLinear, CheckerboardInOneCellIsAllUnresolved) {
  ParticleStore s;
  test::require_basic_fields(s);
  const Range r = s.add_group(0, 27);
  const double f[3] = {0.25, 0.5, 0.75}, sign[3] = {1.0, -2.0, 1.0};
  const double vol = std::pow(kH / 3, 3);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      for (int k = 0; k < 3; ++k) {
        const std::size_t p = r.begin + static_cast<std::size_t>(9 * i + 3 * j + k);
        s.col(Field::x)[p] = (2 + f[i]) * kH;
        s.col(Field::y)[p] = (1 + f[j]) * kH;
        s.col(Field::z)[p] = (3 + f[k]) * kH;
        const double a = sign[i] * sign[j] * sign[k];
        s.col(Field::vx)[p] = 2.0 * a;
        s.col(Field::vy)[p] = -1.0 * a;
        s.col(Field::vz)[p] = 0.5 * a;
        s.col(Field::mass)[p] = kRho * vol;
        s.col(Field::volume0)[p] = vol;
        s.col(Field::size0)[p] = kH / 3;
        s.col(Field::rho)[p] = kRho;
        s.col(IField::id)[p] = static_cast<std::int64_t>(p);
      }
    }
  }
  Simulation sim(config(ShapeKind::linear), std::move(s), elastic(), 1);
  sim.step();
  const EnergyBudget& e = sim.energy();
  ASSERT_GT(e.transferred_kinetic, 0.0);
  EXPECT_NEAR(e.unresolved_kinetic / e.transferred_kinetic, 1.0, 1e-13);
}

// A random field (positions jittered off a lattice, random masses and velocities): 0 <= K_u <= K
// and K_u equals the brute-force P2G of brute_force_unresolved. Both are sums of ~10^3 terms of
// order K with different rounding (exact sum of rounded node terms vs long double): 1e-12 K.
TEST_P(Unresolved, RandomFieldMatchesBruteForce) {
  ParticleStore s;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  test::add_lattice(
      s, 0, Vector3d(0.3, 0.3, 0.3), Vector3d(0.6, 0.6, 0.6), 0.05, kRho,
      [](const Vector3d&) { return true; },
      [&](const Vector3d&) {
        const double a = u(rng), b = u(rng), c = u(rng);
        return Vector3d(0.5 + a, b, c);
      });
  for (std::size_t p = 0; p < s.size(); ++p) {
    for (const Field f : {Field::x, Field::y, Field::z}) s.col(f)[p] += 0.02 * u(rng);
    s.col(Field::mass)[p] *= 1.0 + 0.5 * u(rng);
  }
  long double reference = 0.0L;
  switch (GetParam()) {
    case ShapeKind::linear:
      reference = brute_force_unresolved<kernels::LinearShape>(s);
      break;
    case ShapeKind::ugimp:
      reference = brute_force_unresolved<kernels::GimpShape>(s);
      break;
    case ShapeKind::bspline2:
      reference = brute_force_unresolved<kernels::BSpline2Shape>(s);
      break;
  }
  Simulation sim(config(GetParam()), std::move(s), elastic(), 1);
  sim.step();
  const EnergyBudget& e = sim.energy();
  const double K = e.transferred_kinetic;
  EXPECT_GE(e.unresolved_kinetic, 0.0);
  EXPECT_LE(e.unresolved_kinetic, K);
  // Not a trivial case: random velocities about a mean are largely unresolved.
  EXPECT_GT(e.unresolved_kinetic, 0.1 * K);
  EXPECT_NEAR(e.unresolved_kinetic, static_cast<double>(reference), 1e-12 * K);
}

INSTANTIATE_TEST_SUITE_P(AllShapes, Unresolved,
                         ::testing::Values(ShapeKind::linear, ShapeKind::ugimp,
                                           ShapeKind::bspline2),
                         [](const auto& param_info) {
                           return std::string(name_of(param_info.param));
                         });

// Two bodies in uniform motion towards each other, their stencils overlapping. One shared field:
// the nodes between them average the two velocities, and that relative motion is unresolved (what
// PIC would dissipate). Multi-field contact: each body has its own field, each uniform, so
// nothing is unresolved (1e-13 K as for the translation). Shows body copies are summed, each once.
TEST(UnresolvedContact, BodyFieldsResolveWhatOneSharedFieldDoesNot) {
  auto run = [](ContactKind kind) {
    ParticleStore s;
    test::add_box(s, 0, Vector3d(0.0, 0.0, 0.0), Vector3d(0.4, 0.4, 0.4), 0.05, kRho,
                  Vector3d(1, 0, 0), 0);
    test::add_box(s, 0, Vector3d(0.45, 0.0, 0.0), Vector3d(0.85, 0.4, 0.4), 0.05, kRho,
                  Vector3d(-1, 0, 0), 1);
    SolverConfig cfg = config(ShapeKind::ugimp);
    cfg.contact.kind = kind;
    Simulation sim(cfg, std::move(s), elastic(), 1);
    sim.step();
    return std::pair{sim.energy().unresolved_kinetic, sim.energy().transferred_kinetic};
  };
  const auto [shared, k_shared] = run(ContactKind::single_field);
  const auto [bodies, k_bodies] = run(ContactKind::multi_field);
  EXPECT_EQ(k_shared, k_bodies);
  // The two faces' layers share nodes with relative speed 2: a few % of K, far above round-off.
  EXPECT_GT(shared, 1e-3 * k_shared);
  EXPECT_NEAR(bodies / k_bodies, 0.0, 1e-13);
}
