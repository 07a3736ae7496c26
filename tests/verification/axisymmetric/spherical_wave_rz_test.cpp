// The spherically diverging elastic wave of docs/verification.md ("Spherical elastic wave") run
// in r-z: the same exact solution, initial state and error measures as the 3-D octant
// (tests/support/spherical_wave.hpp), the ball now a quarter disc r^2 + z^2 <= (4a)^2, r, z >= 0,
// with the axis and the plane z = 0 as symmetry faces. The question: does the r-z engine get the
// radial and the hoop stress of a diverging wave right, and converge, where the 3-D engine does?
// The points are the rings of a cell-centred lattice at spacing h / 2 (2 x 2 per cell); the error
// measures weight them equally (an area-weighted L2 in the r-z plane, where the 3-D octant's is
// volume-weighted).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <sstream>
#include <vector>

#include "rz_lattice.hpp"
#include "shatter/material/linear_elastic.hpp"
#include "shatter/mpm/simulation.hpp"
#include "support/spherical_wave.hpp"

using namespace shatter;
using namespace shatter::test::spherical_wave;

namespace {

test::spherical_wave::WaveErrors run_rz(int cells_per_a, ShapeKind shape, double ct_over_a = 2.5) {
  const Elastic m;
  const double h = kA / cells_per_a, R = 4.0 * kA;
  ParticleStore s;
  test::rz::add_rz(
      s, 0, R, 0.0, R, h / 2, kRho, [&](double r, double z) { return r * r + z * z <= R * R; },
      [](double r, double z) { return initial_velocity(Vector3d(r, 0.0, z)); });
  SolverConfig cfg = test::rz::config(h, shape);
  cfg.domain.lo.z() = 0.0;
  cfg.domain.faces[4] = BoundaryKind::symmetry;
  auto mat = std::make_shared<LinearElastic>(kRho, kYoung, kPoisson);
  Simulation sim(cfg, std::move(s), {mat}, 0);
  const double t = ct_over_a * kA / m.c;
  sim.advance_to(t);
  const double t_v = t - 0.5 * sim.clock().dt_prev;  // the leapfrog's v^{n+1/2}
  return measure(sim.particles(), cells_per_a, ct_over_a, t_v, sim.clock().step);
}

}  // namespace

// Tolerances. Measured with the quadratic B-spline (relative to the exact peak |s_rr|; L2 over
// the points within the pulse's support + 2 h; docs/validation-axisymmetric.md), a/h = 8 / 16:
//   s_rr L2 0.513 / 0.179, max 1.28 / 0.49;  s_tt L2 0.104 / 0.034, max 0.30 / 0.093;
//   v_r L2 0.508 / 0.176; non-spherical part 0.0088 / 0.0034; largest shell-mean hoop tension
//   -12 % / +8.1 % of the exact one.
// (The 3-D octant with uGIMP at a/h = 8: s_rr L2 0.327, s_tt L2 0.064: the r-z run at a/h = 16
// costs 12 867 points against the octant's ~1e5 at a/h = 8.) As in 3-D the error is mostly the
// pulse's phase lag, and it falls at order 1.5-1.6 from 8 to 16. Bounds, at a/h = 16: 1.25x the
// measured L2 and max errors; the hoop tension within 12 % (1.5x the measured 8.1 %); the
// stress's departure from diag(s_rr, s_tt, s_tt) in the local frame (which a wrong hoop term
// or a mis-folded axis produces) below 0.005; and the 8 -> 16 error ratio above 2 (order > 1;
// an error that does not vanish with h, e.g. a missing hoop term, fails it).
TEST(SphericalWaveRz, RadialAndHoopStressMatchExactAndConverge) {
  const WaveErrors coarse = run_rz(8, ShapeKind::bspline2);
  const WaveErrors e = run_rz(16, ShapeKind::bspline2);
  print("r-z spherical wave", 8, coarse);
  print("r-z spherical wave", 16, e);
  EXPECT_LT(e.srr_l2, 0.22);
  EXPECT_LT(e.stt_l2, 0.043);
  EXPECT_LT(e.v_l2, 0.22);
  EXPECT_LT(e.srr_max, 0.61);
  EXPECT_LT(e.stt_max, 0.12);
  EXPECT_LT(e.tangential_l2, 0.005);
  EXPECT_GT(e.stt_tension, 0.0);
  EXPECT_NEAR(e.stt_tension / e.stt_tension_exact, 1.0, 0.12);
  EXPECT_GT(coarse.srr_l2 / e.srr_l2, 2.0);
  EXPECT_GT(coarse.stt_l2 / e.stt_l2, 2.0);
}

// The study behind the figure (not a check): SPHERICAL_WAVE_RZ_CELLS="4 8 16 32" prints the
// errors and the shell profiles for each a/h, linear and B-spline shapes.
TEST(SphericalWaveRz, Study) {
  const char* env = std::getenv("SPHERICAL_WAVE_RZ_CELLS");
  if (env == nullptr) GTEST_SKIP() << "set SPHERICAL_WAVE_RZ_CELLS to run the study";
  std::istringstream in(env);
  int n = 0;
  while (in >> n) {
    for (const ShapeKind shape : {ShapeKind::linear, ShapeKind::bspline2}) {
      const WaveErrors e = run_rz(n, shape);
      print(shape == ShapeKind::linear ? "rz linear" : "rz bspline2", n, e);
      for (const auto& row : e.profile) {
        std::cout << "profile " << name_of(shape) << ' ' << n;
        for (const double v : row) std::cout << ' ' << v;
        std::cout << '\n';
      }
    }
  }
}
