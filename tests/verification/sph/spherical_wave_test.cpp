// Spherically diverging elastic wave with SPH against its exact solution (issue 10, Validation
// "Elastic waves"; docs/validation-sph.md). The same problem, exact solution, octant set-up and
// error measures as the MPM test tests/verification/mpm/spherical_wave_test.cpp (derivation
// there and in studies/verification/spherical_wave.py), so the two methods' numbers stand side by
// side: only the solver differs. "h" below is the MPM cell size of that test, a / cells_per_a, and
// the points sit 2 x 2 x 2 per cell (spacing h / 2), so a/h means the same number of points in
// both; the SPH smoothing length is h_factor x spacing (1.2 by default, 0.6 h). The three symmetry
// planes are the SPH solver's mirror particles (corner and edge images included).
//
// Exact solution (from the MPM test). Linear elasticity, irrotational motion u = grad(phi),
// phi_tt = c_p^2 lap(phi); with w = r phi, w_tt = c_p^2 w_rr and
//   u_r  = w_r / r - w / r^2,              v_r = w_rt / r - w_t / r^2,
//   s_rr = M w_rr / r - 4 G (w_r / r^2 - w / r^3),                          (1)
//   s_tt = lambda w_rr / r + 2 G (w_r / r^2 - w / r^3),                     (2)
// from rest with v0 = grad(psi0), psi0 = A (1 - r^2/a^2)^3 on r < a:
// w = F(r - c t) - F(r + c t), F(s) = A a^2 / (16 c) (1 - s^2/a^2)^4 on |s| < a.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "shatter/material/linear_elastic.hpp"
#include "shatter/sph/solver.hpp"
#include "support/lattice.hpp"

#include "support/spherical_wave.hpp"
using namespace shatter;
using Eigen::Vector3d;

using namespace shatter::test::spherical_wave;

namespace {

// Bounds of the CI test at a/h = 4 (s_rr L2, s_tt L2, v_r L2, non-spherical part): 1.25x the
// measured values (see the test).
constexpr std::array<double, 4> kBound{0.44, 0.092, 0.42, 0.003};

// Runs the octant (SPH, mirror particles on the three symmetry planes) at h = a / cells_per_a to c
// t = ct_over_a a and measures it against the exact solution (support/spherical_wave.hpp; h is
// the MPM cell, 2 point spacings, about the SPH smoothing length's 2.4 spacings of support).
WaveErrors run_spherical_wave(int cells_per_a, double ct_over_a = 2.5, double ct0_over_a = 0.0,
                              double h_factor = 1.2) {
  const Elastic m;
  auto mat = std::make_shared<LinearElastic>(kRho, kYoung, kPoisson);
  const double t0 = ct0_over_a * kA / m.c;
  const SolverConfig cfg = octant_config(cells_per_a);
  sph::SphConfig sc;
  sc.h_factor = h_factor;
  sph::SphSolver sim(cfg, sc, make_octant(cells_per_a, ct0_over_a), {mat}, 0);
  const double t = ct_over_a * kA / m.c;
  sim.advance_to(t - t0);
  const double t_v = t - 0.5 * sim.clock().dt_prev;
  // the leapfrog's v^{n+1/2}
  return measure(sim.particles(), cells_per_a, ct_over_a, t_v, sim.clock().step);
}

}  // namespace

// Tolerances, a/h = 4 (17 172 points, 123 steps, ~4.5 s CPU in Release). Measured (relative to
// the exact peak |s_rr|, as the MPM test): s_rr L2 0.354, s_tt L2 0.0732, v_r L2 0.340,
// non-spherical part 0.0024; shell-mean hoop tension 0.80 and radial tension 0.76 of the exact
// ones (docs/validation-sph.md, "Spherical elastic wave", where the convergence study shows the
// errors falling with the spacing). Bounds: 1.25x the measured errors, so a regression of a
// quarter fails; hoop and radial tension positive and within 30 % of exact (the SPH pulse is
// smeared, so its lobes are low at this coarse resolution; an inverted or mis-mirrored wave has
// the wrong sign; checked: an inverted initial velocity fails the three L2 bounds, s_rr L2
// 0.60, and the radial-tension check). The question is the MPM test's: the radial and the hoop
// stress of a diverging wave, and the tension behind it, here from the SPH stress divergence and
// mirror planes.
TEST(SphSphericalWave, RadialAndHoopStressMatchExact) {
  const WaveErrors e = run_spherical_wave(4);
  print("SPH spherical wave", 4, e);
  EXPECT_LT(e.srr_l2, kBound[0]);
  EXPECT_LT(e.stt_l2, kBound[1]);
  EXPECT_LT(e.v_l2, kBound[2]);
  ASSERT_GT(e.stt_tension_exact, 0.15 * e.peak);  // the exact pulse does carry hoop tension
  EXPECT_NEAR(e.stt_tension / e.stt_tension_exact, 1.0, 0.30);
  EXPECT_NEAR(e.srr_tension / e.srr_tension_exact, 1.0, 0.30);
  EXPECT_LT(e.tangential_l2, kBound[3]);
}

// The convergence study of docs/validation-sph.md (minutes; run with
// --gtest_also_run_disabled_tests --gtest_filter='*SphSphericalWave*'). SPH_SPHERICAL_WAVE_CSV=
// prefix writes prefix<a/h>.csv with the shell-mean profiles (the MPM study's columns);
// SPH_SPHERICAL_WAVE_LEVELS="4,6,8" picks the resolutions; SPH_SPHERICAL_WAVE_H=1.3 the h_factor.
TEST(SphSphericalWave, DISABLED_ConvergenceStudy) {
  const char* prefix = std::getenv("SPH_SPHERICAL_WAVE_CSV");
  const char* levels = std::getenv("SPH_SPHERICAL_WAVE_LEVELS");
  const char* hf = std::getenv("SPH_SPHERICAL_WAVE_H");
  const double h_factor = hf ? std::atof(hf) : 1.2;
  std::vector<int> ns{4, 6, 8};
  if (levels != nullptr) {
    ns.clear();
    for (const char* c = levels; *c != 0;) {
      ns.push_back(std::atoi(c));
      while (*c != 0 && *c != ',') ++c;
      if (*c == ',') ++c;
    }
  }
  for (const int n : ns) {
    const WaveErrors e = run_spherical_wave(n, 2.5, 0.0, h_factor);
    print("study", n, e);
    if (prefix == nullptr) continue;
    std::ofstream csv(std::string(prefix) + std::to_string(n) + ".csv");
    csv << "r_m,srr_mpm_Pa,srr_exact_Pa,stt_mpm_Pa,stt_exact_Pa,vr_mpm_m_per_s,vr_exact_m_per_s\n";
    for (const auto& row : e.profile) {
      for (std::size_t k = 0; k < row.size(); ++k) csv << (k ? "," : "") << row[k];
      csv << "\n";
    }
  }
}
