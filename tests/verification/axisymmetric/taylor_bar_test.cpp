// The Taylor bar (Wilkins & Guinan 1973, J. Appl. Phys. 44, 1200): the copper rod of
// scenes/verification/taylor-rz.toml (length 32.4 mm, radius 3.2 mm, 227 m/s onto a rigid
// frictionless wall, J2 plasticity with linear hardening) to 80 us, run from the scene files in
// r-z and as the 3-D half model (taylor-3d.toml) at a coarse 0.8 mm cell (4 cells per radius), so
// that the 3-D run takes seconds, and in r-z at 0.4 mm against the benchmark. The final length is
// measured on the points' cells, L = max z - min z + s (s the point spacing: L0 exactly for the
// initial rod); the mushroom radius as R0 plus the outward displacement of the outermost point,
// R = R0 + max r - max r_initial (the 3-D lattice's outermost point is not at R0 - s / 2, the r-z
// one is, so that R = max r + s / 2 there).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <string>

#include "shatter/core/solver.hpp"
#include "shatter/scene/build.hpp"
#include "shatter/scene/scene.hpp"
#include "support/sanitizers.hpp"

using namespace shatter;

namespace {

constexpr double kL0 = 32.4e-3, kR0 = 3.2e-3;  // m, taylor-rz.toml

struct Shape {
  double length = 0.0, radius = 0.0, cpu_s = 0.0;
};

// L on the points' cells and the largest r (R is formed by the caller).
Shape measure(const ParticleStore& P, double s) {
  double zlo = 1e300, zhi = -1e300, rmax = 0.0;
  for (std::size_t p = 0; p < P.size(); ++p) {
    zlo = std::min(zlo, P.col(Field::z)[p]);
    zhi = std::max(zhi, P.col(Field::z)[p]);
    rmax = std::max(rmax, std::hypot(P.col(Field::x)[p], P.col(Field::y)[p]));
  }
  return {zhi - zlo + s, rmax, 0.0};
}

// Runs the scene file at cell size h (2 points per cell) to its end time (80 us).
Shape run(const std::string& file, double h) {
  const scene::Scene sc =
      scene::load_scene(std::string(SHATTER_SOURCE_DIR) + "/scenes/verification/" + file,
                        {"solver.cell_size=" + std::to_string(h)});
  scene::BuiltScene built = scene::build(sc);
  auto solver = scene::make_solver(sc, std::move(built.particles), built.materials, 1);
  const Shape initial = measure(solver->particles(), 0.5 * h);
  EXPECT_NEAR(initial.length, kL0, 1e-9) << file;
  const std::clock_t c0 = std::clock();  // one thread: process CPU time is the run's
  solver->advance_to(sc.end_time);
  Shape out = measure(solver->particles(), 0.5 * h);
  out.radius = kR0 + out.radius - initial.radius;
  out.cpu_s = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  std::printf("%s h = %.2g mm: L/L0 = %.4f, R/R0 = %.4f, %.2f s\n", file.c_str(), h * 1e3,
              out.length / kL0, out.radius / kR0, out.cpu_s);
  return out;
}

}  // namespace

// Tolerances (measured, docs/validation-axisymmetric.md "Taylor bar"). At h = 0.8 mm (4 cells
// per radius) r-z gives L/L0 = 0.6818, R/R0 = 1.943 and the 3-D half model 0.6831 / 1.984: gaps
// of 0.2 % and 2.1 %; bounds 1 % and 4 % (about twice the gaps: the two runs differ only in the
// geometry, which r-z carries exactly and the 3-D lattice staircases on a 4-cell radius; at
// 0.4 mm the R gap is 5 %, the 3-D foot spreading further along the lattice's axes). r-z at
// 0.4 mm gives L = 21.80 mm, R = 7.17 mm; the benchmark's converged solutions (Kamoulakos 1990,
// Zhu & Cescotto 1995) have L = 21.42-21.66 mm and R = 7.0-7.2 mm: bounds 2.5 % of the band's
// middle L (21.55 mm) and 4 % of its middle R (7.1 mm), the band's half-width plus 1.5-2.5 % for
// an 8-cell radius (r-z moves L by 1.3 % and R by 15 % from 4 to 8 cells per radius).
TEST(TaylorBar, RzAgreesWith3dAndTheBenchmark) {
  const Shape rz = run("taylor-rz.toml", 0.8e-3);
  const Shape d3 = run("taylor-3d.toml", 0.8e-3);
  EXPECT_NEAR(rz.length / d3.length, 1.0, 0.01);
  EXPECT_NEAR(rz.radius / d3.radius, 1.0, 0.04);
  // Reduced form under the sanitizers (support/sanitizers.hpp): the 0.4 mm r-z run (45 % of the
  // test's time) runs the same r-z code as the 0.8 mm one above; its benchmark bounds are
  // Release checks.
  if (test::kUnderSanitizers) return;
  const Shape fine = run("taylor-rz.toml", 0.4e-3);
  EXPECT_NEAR(fine.length / 21.55e-3, 1.0, 0.025);
  EXPECT_NEAR(fine.radius / 7.1e-3, 1.0, 0.04);
}
