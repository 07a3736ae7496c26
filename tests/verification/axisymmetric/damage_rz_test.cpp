// Grady-Kipp damage in r-z (issue 31): a ring holds the flaws of one 3-D point of its
// cross-section's size and grows its damage over that point's R_s (src/fracture/flaws.cpp,
// kernels/constitutive/composed_kernel.hpp), so that the failed fraction of a body in r-z is that
// of the 3-D body at the same spacing, and does not depend on the spacing more than in 3-D.
// The case: a basalt rod (radius 10 mm, length 40 mm, the half z > 0 with z = 0 a symmetry
// plane) started on a uniform axial stretching v_z = rate z and left free: tension builds in
// its middle and the flaws of the MPM paper's resolution-independent scheme break it. Measured:
// the mass fraction with D >= 0.9 every 2 us, r-z against the 3-D quarter model (x = 0 and
// y = 0 symmetry planes).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "rz_lattice.hpp"
#include "shatter/fracture/flaws.hpp"
#include "shatter/material/catalogue.hpp"
#include "shatter/mpm/simulation.hpp"

using namespace shatter;
using Eigen::Vector3d;

namespace {

constexpr double kR = 0.01, kH = 0.02, kRate = 400.0;  // m, m (half length), 1/s
constexpr double kSample = 2.0e-6, kEnd = 16.0e-6;     // s

// Mass fraction of the points with D >= 0.9.
double failed(const ParticleStore& P) {
  double all = 0.0, broken = 0.0;
  for (std::size_t p = 0; p < P.size(); ++p) {
    all += P.col(Field::mass)[p];
    if (P.col(Field::damage)[p] >= 0.9) broken += P.col(Field::mass)[p];
  }
  return broken / all;
}

// The failed fraction at kSample, 2 kSample, ..., kEnd of the rod at cell h (2 points per cell).
// rings = false in r-z draws the flaws as if each ring were one 3-D point (the fault the ring
// weighting removes), for the check that the test can tell.
std::vector<double> run(bool rz, double h, bool rings = true) {
  const DamageSpec damage{"grady_kipp",
                          {{"weibull_m", 8.5}, {"weibull_k", 3.0e39}, {"total_flaws", 1.0e10}}};
  const MaterialSpec basalt = MaterialCatalogue::builtin().get("basalt");
  const MaterialPtr material = make_material(basalt, damage);
  const double rho = basalt.get("rho0");
  ParticleStore s;
  const auto stretch = [](double z) { return Vector3d(0.0, 0.0, kRate * z); };
  const Range r =
      rz ? test::rz::add_rz(
               s, 0, kR, 0.0, kH, h / 2, rho, [](double, double) { return true; },
               [&](double, double z) { return stretch(z); })
         : test::add_lattice(
               s, 0, Vector3d(0, 0, 0), Vector3d(kR, kR, kH), h / 2, rho,
               [](const Vector3d& x) { return x.x() * x.x() + x.y() * x.y() <= kR * kR; },
               [&](const Vector3d& x) { return stretch(x.z()); });
  s.require(material->fields());
  FlawSpec flaws = flaw_spec_from_params(damage.params, basalt.get("young"));
  flaws.rings = rz && rings;
  initialise_flaws(s, r, flaws, rz ? 2 : 8);  // the whole rod: r-z holds 1/2, 3-D 1/8
  SolverConfig cfg = rz ? test::rz::config(h) : SolverConfig{};
  cfg.shape = ShapeKind::bspline2;
  cfg.cell_size = h;
  for (int axis = 0; axis < 3; ++axis) {
    if (rz && axis == 1) continue;
    cfg.domain.lo[axis] = 0.0;
    cfg.domain.faces[static_cast<std::size_t>(2 * axis)] = BoundaryKind::symmetry;
  }
  Simulation sim(cfg, std::move(s), {material}, 1);
  std::vector<double> out;
  for (double t = kSample; t <= kEnd + 1e-12; t += kSample) {
    sim.advance_to(t);
    out.push_back(failed(sim.particles()));
  }
  std::printf("%s h = %.2g mm%s:", rz ? "r-z" : "3-D", h * 1e3, rings ? "" : " (unweighted)");
  for (const double f : out) std::printf(" %.3f", f);
  std::printf("\n");
  return out;
}

double max_gap(const std::vector<double>& a, const std::vector<double>& b) {
  double g = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) g = std::max(g, std::abs(a[k] - b[k]));
  return g;
}

}  // namespace

// Tolerances. Measured (mass fraction failed at 2, 4, ..., 16 us; docs/validation-axisymmetric.md):
//   3-D quarter, 1 mm:   0.000 0.304 0.322 0.347 0.366 0.381 0.389 0.399
//   r-z, 1 mm:           0.000 0.267 0.331 0.336 0.355 0.365 0.377 0.388
//   r-z, 0.5 mm:         0.000 0.221 0.265 0.289 0.302 0.313 0.319 0.324
//   r-z, 1 mm, each ring drawn as one 3-D point: 0.000 0.246 0.305 0.307 0.331 0.346 0.349 0.353
// r-z against 3-D: largest gap 0.036, 0.011 at the end; bound 0.05 on the largest gap and 0.03
// at the end (the flaws are random draws: ~400 rings against ~12 500 points, whose sampling
// spread of a 0.4 fraction is ~0.025). The unweighted draw ends 0.046 below 3-D, outside the
// end bound. r-z from 1 to 0.5 mm: largest gap 0.066, where the 3-D quarter's own is 0.051
// (DISABLED_Study3dAtHalfTheSpacing: 0.000 0.253 0.296 0.315 0.335 0.346 0.357 0.365 at 0.5 mm;
// the Grady-Kipp damage at 10-20 points per radius is not converged in either); bound 0.1.
TEST(DamageRz, FailedFractionMatches3dAndIsResolutionIndependent) {
  const auto d3 = run(false, 1.0e-3);
  const auto rz = run(true, 1.0e-3);
  const auto rz_fine = run(true, 0.5e-3);
  EXPECT_LT(max_gap(rz, d3), 0.05);
  EXPECT_NEAR(rz.back(), d3.back(), 0.03);
  EXPECT_LT(max_gap(rz, rz_fine), 0.1);
  const auto rz_unweighted = run(true, 1.0e-3, false);
  EXPECT_GT(std::abs(rz_unweighted.back() - d3.back()), 0.03);  // the test tells the fault
  EXPECT_GT(d3[1], 0.2);  // the rod does break (a test that cannot fail is no test)
}

// The 3-D quarter at 0.5 mm (~100 000 points, ~20 s): how much the 3-D engine's failed fraction
// moves with the spacing, for the r-z bound above. Run with --gtest_also_run_disabled_tests.
TEST(DamageRz, DISABLED_Study3dAtHalfTheSpacing) {
  const auto coarse = run(false, 1.0e-3);
  const auto fine = run(false, 0.5e-3);
  std::printf("3-D 1 vs 0.5 mm: largest gap %.3f\n", max_gap(coarse, fine));
}
