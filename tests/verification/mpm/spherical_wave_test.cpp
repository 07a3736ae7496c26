// Spherically diverging elastic wave against its exact solution (docs/verification.md,
// "Spherical elastic wave"). The question it answers: does the engine get the radial and the hoop
// stress of a diverging wave, and the tension behind it, right (docs/validation-lab-impact.md,
// Sec. 5, check 1)?
//
// Exact solution (derived in studies/verification/spherical_wave.py, which also checks it by
// differences). Linear elasticity, irrotational motion u = grad(phi), phi_tt = c_p^2 lap(phi). With
// spherical symmetry w = r phi solves the 1D wave equation w_tt = c_p^2 w_rr, and
//   u_r  = w_r / r - w / r^2,              v_r = w_rt / r - w_t / r^2,
//   s_rr = M w_rr / r - 4 G (w_r / r^2 - w / r^3),                          (1)
//   s_tt = lambda w_rr / r + 2 G (w_r / r^2 - w / r^3),                     (2)
// M = lambda + 2 G (s_tt = lambda div u + 2 G u_r / r: the hoop stress is where u_r / r enters).
// Initial state: no displacement, no stress, velocity v0 = grad(psi0) with the C^2 bump
// psi0 = A (1 - r^2/a^2)^3 on r < a. Then phi(r, 0) = 0, phi_t(r, 0) = psi0, and d'Alembert with
// the odd extension of r psi0 gives w = F(r - c t) - F(r + c t), F(s) = A a^2 / (16 c) (1 -
// s^2/a^2)^4 on |s| < a. For c t > a only the outgoing pulse F(r - c t) / r is left, on |r - c t| <
// a.
//
// A velocity start rather than Sharpe's pressurised cavity: the initial state needs no initial
// stress and no cavity surface (both of which the engine would have to resolve), the solution is
// a closed-form polynomial, and the wave is compact, so there is an exact zero behind it and the
// "tail" is unambiguous.
//
// Octant model: symmetry planes x = y = z = 0 (the engine folds all three in turn,
// Boundaries::mirror), a ball of radius R = 4 a, so the outgoing pulse at c t = 2.5 a
// (1.5 a < r < 3.5 a) has not reached the free surface. Material: the laboratory target's basalt
// elasticity (E = 53.1 GPa, nu = 0.15), uGIMP, 2 x 2 x 2 points per cell, FLIP: as the lab impact.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "shatter/material/linear_elastic.hpp"
#include "shatter/mpm/simulation.hpp"
#include "support/lattice.hpp"
#include "support/spherical_wave.hpp"

using namespace shatter;
using Eigen::Vector3d;

using namespace shatter::test::spherical_wave;

namespace {

// The particle-grid transfer of a run, as the scene keys solver.transfer, pic_fraction,
// xpic_order and fmpm_order (docs/verification.md, "Transfer schemes"); default FLIP.
struct Transfer {
  TransferKind kind = TransferKind::flip;
  double pic_fraction = 0.0;
  int xpic_order = 5;
  int fmpm_order = 5;
  void apply(SolverConfig& cfg) const {
    cfg.transfer = kind;
    cfg.pic_fraction = pic_fraction;
    cfg.xpic_order = xpic_order;
    cfg.fmpm_order = fmpm_order;
  }
  // docs/convergence.csv's scheme suffix (studies/convergence/plot_convergence.py): none for FLIP,
  // _pic<f> for the blend (_pic1: PIC), _xpic<m>, _fmpm<k>, _apic.
  std::string suffix() const {
    std::ostringstream s;
    if (kind == TransferKind::apic) s << "_apic";
    if (kind == TransferKind::xpic) s << "_xpic" << xpic_order;
    if (kind == TransferKind::fmpm) s << "_fmpm" << fmpm_order;
    if (kind == TransferKind::flip && pic_fraction > 0.0) s << "_pic" << pic_fraction;
    return s.str();
  }
};

// SPHERICAL_WAVE_TRANSFER, _PIC_FRACTION, _XPIC_ORDER, _FMPM_ORDER (the study only); bad values
// throw, naming the variable.
Transfer transfer_from_environment() {
  Transfer t;
  if (const char* kind = std::getenv("SPHERICAL_WAVE_TRANSFER")) {
    const std::string k = kind;
    if (k == "flip") {
      t.kind = TransferKind::flip;
    } else if (k == "apic") {
      t.kind = TransferKind::apic;
    } else if (k == "xpic") {
      t.kind = TransferKind::xpic;
    } else if (k == "fmpm") {
      t.kind = TransferKind::fmpm;
    } else {
      throw std::invalid_argument("SPHERICAL_WAVE_TRANSFER=" + k +
                                  ": expected flip, apic, xpic or fmpm");
    }
  }
  if (const char* f = std::getenv("SPHERICAL_WAVE_PIC_FRACTION")) {
    char* end = nullptr;
    t.pic_fraction = std::strtod(f, &end);
    if (end == f || *end != '\0' || !(t.pic_fraction >= 0.0 && t.pic_fraction <= 1.0) ||
        t.kind != TransferKind::flip) {
      throw std::invalid_argument(std::string("SPHERICAL_WAVE_PIC_FRACTION=") + f +
                                  ": expected a number in [0, 1], with the flip transfer");
    }
  }
  if (const char* m = std::getenv("SPHERICAL_WAVE_XPIC_ORDER")) {
    char* end = nullptr;
    const long order = std::strtol(m, &end, 10);
    if (end == m || *end != '\0' || order < 1 || order > 32 || t.kind != TransferKind::xpic) {
      throw std::invalid_argument(std::string("SPHERICAL_WAVE_XPIC_ORDER=") + m +
                                  ": expected an integer in [1, 32], with the xpic transfer");
    }
    t.xpic_order = static_cast<int>(order);
  }
  if (const char* m = std::getenv("SPHERICAL_WAVE_FMPM_ORDER")) {
    char* end = nullptr;
    const long order = std::strtol(m, &end, 10);
    if (end == m || *end != '\0' || order < 1 || order > 32 || t.kind != TransferKind::fmpm) {
      throw std::invalid_argument(std::string("SPHERICAL_WAVE_FMPM_ORDER=") + m +
                                  ": expected an integer in [1, 32], with the fmpm transfer");
    }
    t.fmpm_order = static_cast<int>(order);
  }
  return t;
}

// SPHERICAL_WAVE_CELLS=4,6,8: the resolutions a/h of the study (the default when unset).
std::vector<int> cells_from_environment(std::vector<int> fallback) {
  const char* list = std::getenv("SPHERICAL_WAVE_CELLS");
  if (list == nullptr) return fallback;
  std::vector<int> cells;
  std::istringstream in(list);
  std::string item;
  while (std::getline(in, item, ',')) {
    char* end = nullptr;
    const long n = std::strtol(item.c_str(), &end, 10);
    if (item.empty() || *end != '\0' || n < 2 || n > 64) {
      throw std::invalid_argument(std::string("SPHERICAL_WAVE_CELLS=") + list +
                                  ": expected comma-separated integers a/h in [2, 64]");
    }
    cells.push_back(static_cast<int>(n));
  }
  return cells;
}

// Runs the octant at h = a / cells_per_a to c t = ct_over_a a and measures it against the exact
// solution (support/spherical_wave.hpp). `transfer` sets the particle-grid transfer (FLIP, the
// default, in the enabled tests; the study takes it from the environment).
WaveErrors run_spherical_wave(int cells_per_a, double ct_over_a = 2.5, double ct0_over_a = 0.0,
                              const Transfer& transfer = {}) {
  const Elastic m;
  auto mat = std::make_shared<LinearElastic>(kRho, kYoung, kPoisson);
  const double t0 = ct0_over_a * kA / m.c;
  SolverConfig cfg = octant_config(cells_per_a);
  transfer.apply(cfg);
  Simulation sim(cfg, make_octant(cells_per_a, ct0_over_a), {mat}, 0);
  const double t = ct_over_a * kA / m.c;
  sim.advance_to(t - t0);
  const double t_v = t - 0.5 * sim.clock().dt_prev;
  // the leapfrog's v^{n+1/2}
  return measure(sim.particles(), cells_per_a, ct_over_a, t_v, sim.clock().step);
}

}  // namespace

// Tolerances. Measured (docs/verification.md, "Spherical elastic wave"; relative to the exact
// peak |s_rr|, L2 over the points within the pulse's support + 2 h), a/h = 6 / 8:
//   s_rr L2 0.473 / 0.327, max 1.42 / 0.88;  s_tt L2 0.095 / 0.064, max 0.38 / 0.20;
//   v_r L2 0.468 / 0.318 (relative to max |v_r|).
// The error is almost all a phase lag of the pulse (0.6-0.8 h behind at c t = 2.5 a, most of it
// picked up where the initial pulse focuses through the centre), which is why it is large at
// these coarse resolutions and why it shrinks faster than h (observed order 1.3-1.5 from a/h = 6
// to 16, rising). Bounds, for a/h = 8: 1.25x the measured L2 and max errors. Halving the error
// needs a/h x 1.6 at order 1.5; the bound on the 6 -> 8 ratio, 1.3 (measured 1.45-1.48), asks for
// better than order 0.9; an error that does not vanish with h (a mis-folded symmetry plane, a
// wrong modulus) fails it. Checked: an inverted initial velocity fails 10 of the 13 checks
// (s_rr L2 0.87); a Poisson ratio of 0.25 in the engine for 0.15 fails the hoop checks (s_tt L2
// 0.087, hoop tension +73%) but *lowers* the s_rr L2 to 0.17, because its faster wave (+6.6%)
// cancels the lag: s_rr alone is a weak check at this resolution, s_tt is the sharp one.
// The question this test exists for is the hoop stress and the tension that follows the pulse
// (lab impact, docs/validation-lab-impact.md Sec. 5): the largest shell-mean hoop tension must
// be within 10% of the exact one at a/h = 8 (measured -2.5%; -15% at a/h = 6) and the largest
// radial tension within 15% (measured +11%), both positive. The grid-scale noise (each point's
// error about its shell mean) is a quarter of the error (0.08 of the peak at a/h = 8): bound
// 0.1. Deviation from the spherically symmetric stress diag(s_rr, s_tt, s_tt), 0.019: bound 0.03.
TEST(SphericalWave, RadialAndHoopStressMatchExact) {
  const WaveErrors coarse = run_spherical_wave(6);
  const WaveErrors e = run_spherical_wave(8);
  print("spherical wave", 6, coarse);
  print("spherical wave", 8, e);
  EXPECT_LT(e.srr_l2, 0.41);
  EXPECT_LT(e.stt_l2, 0.08);
  EXPECT_LT(e.v_l2, 0.40);
  EXPECT_LT(e.srr_max, 1.1);
  EXPECT_LT(e.stt_max, 0.26);
  EXPECT_GT(coarse.srr_l2 / e.srr_l2, 1.3);
  EXPECT_GT(coarse.stt_l2 / e.stt_l2, 1.3);
  EXPECT_GT(coarse.v_l2 / e.v_l2, 1.3);
  ASSERT_GT(e.stt_tension_exact, 0.15 * e.peak);  // the exact pulse does carry hoop tension
  EXPECT_NEAR(e.stt_tension / e.stt_tension_exact, 1.0, 0.10);
  EXPECT_NEAR(e.srr_tension / e.srr_tension_exact, 1.0, 0.15);
  EXPECT_LT(e.srr_noise, 0.1);
  EXPECT_LT(e.tangential_l2, 0.03);
}

// The octant rests on three symmetry planes meeting at the centre, where the pulse focuses;
// symmetry_plane_test.cpp checks one plane only. The octant must reproduce the full ball's points
// in x, y, z > 0: the runs differ only in the order of the nodal sums (folds against direct
// scatter), so to round-off, 1e-9 relative after 25 steps as for one plane. Even a slip plane in
// place of the mirror at z = 0, which is nearly right for this symmetric flow, differs by 1.2e-4
// (stress) and 1.2e-5 (velocity), five orders above the bound.
TEST(SphericalWave, OctantOnThreeSymmetryPlanesMatchesFullBall) {
  const Elastic m;
  std::vector<MaterialPtr> mat{std::make_shared<LinearElastic>(kRho, kYoung, kPoisson)};
  const double h = kA / 3, R = 4.0 * kA;
  auto ball = [&](const Vector3d& lo) {
    ParticleStore s;
    test::add_lattice(
        s, 0, lo, Vector3d::Constant(R), h / 2, kRho,
        [&](const Vector3d& x) { return x.norm() <= R; }, initial_velocity);
    return s;
  };
  ParticleStore full_store = ball(Vector3d::Constant(-R));
  ParticleStore octant_store = ball(Vector3d::Zero());
  // Partner of each octant point in the full ball, by initial position (ids are lattice order).
  std::map<std::array<long long, 3>, std::int64_t> full_id;
  auto key = [&](const ParticleStore& s, std::size_t p) {
    return std::array<long long, 3>{std::llround(s.col(Field::x)[p] / (h / 4)),
                                    std::llround(s.col(Field::y)[p] / (h / 4)),
                                    std::llround(s.col(Field::z)[p] / (h / 4))};
  };
  for (std::size_t p = 0; p < full_store.size(); ++p) {
    full_id[key(full_store, p)] = full_store.col(IField::id)[p];
  }
  std::map<std::int64_t, std::int64_t> partner;  // octant id -> full id
  for (std::size_t p = 0; p < octant_store.size(); ++p) {
    partner[octant_store.col(IField::id)[p]] = full_id.at(key(octant_store, p));
  }
  ASSERT_EQ(8 * octant_store.size(), full_store.size());
  SolverConfig full_cfg;
  full_cfg.cell_size = h;
  // Pinned below the CFL step (0.3 h / (c + |v|)), so that a round-off difference in the
  // largest velocity cannot make the two runs step to different times.
  full_cfg.dt_max = 0.25 * h / m.c;
  SolverConfig octant_cfg = full_cfg;
  octant_cfg.domain.lo = Vector3d::Zero();
  octant_cfg.domain.faces = {BoundaryKind::symmetry, BoundaryKind::none,     BoundaryKind::symmetry,
                             BoundaryKind::none,     BoundaryKind::symmetry, BoundaryKind::none};
  Simulation full(full_cfg, std::move(full_store), mat, 0);
  Simulation octant(octant_cfg, std::move(octant_store), mat, 0);
  for (int k = 0; k < 25; ++k) {  // c t = 2.1 a: the pulse has passed through the centre
    full.step();
    octant.step();
    ASSERT_EQ(full.clock().dt, octant.clock().dt) << "step " << k;
  }
  const ParticleStore& F = full.particles();
  const ParticleStore& O = octant.particles();
  std::map<std::int64_t, std::size_t> index;
  for (std::size_t p = 0; p < F.size(); ++p) index[F.col(IField::id)[p]] = p;
  double worst_v = 0, worst_s = 0, vmax = 0;
  const double smax = test::max_abs_stress(F);
  for (std::size_t q = 0; q < O.size(); ++q) {
    const std::size_t p = index.at(partner.at(O.col(IField::id)[q]));
    for (const Field f : {Field::vx, Field::vy, Field::vz}) {
      worst_v = std::max(worst_v, std::abs(O.col(f)[q] - F.col(f)[p]));
      vmax = std::max(vmax, std::abs(F.col(f)[p]));
    }
    for (const Field f : {Field::sxx, Field::syy, Field::szz, Field::sxy, Field::syz, Field::sxz}) {
      worst_s = std::max(worst_s, std::abs(O.col(f)[q] - F.col(f)[p]));
    }
  }
  EXPECT_LT(worst_v / vmax, 1e-9);
  EXPECT_LT(worst_s / smax, 1e-9);
  EXPECT_GT(smax, 1e5);  // the pulse did load the ball (peak |s_rr| ~1e6 Pa)
}

// The convergence study of docs/verification.md (minutes; run with
// --gtest_also_run_disabled_tests --gtest_filter='*SphericalWave*'). Environment:
//   SPHERICAL_WAVE_CSV=prefix        writes prefix<a/h>.csv with the shell-mean profiles;
//   SPHERICAL_WAVE_CT0=1.2           starts from the exact outgoing state at c t0 = 1.2 a;
//   SPHERICAL_WAVE_CELLS=6,8,12      the resolutions a/h (default 4,6,8,12,16);
//   SPHERICAL_WAVE_TRANSFER=flip|apic|xpic, SPHERICAL_WAVE_PIC_FRACTION=f (FLIP/PIC blend),
//   SPHERICAL_WAVE_XPIC_ORDER=m      the transfer scheme, as the scene keys solver.transfer,
//                                    pic_fraction, xpic_order (default FLIP, as the lab impact);
//   SPHERICAL_WAVE_STUDY_CSV=file    appends one row per resolution in docs/convergence.csv's
//                                    format (problem spherical_wave_srr[_scheme], the s_rr L2
//                                    error, the run's CPU time in wall_s: run it with
//                                    OMP_NUM_THREADS=1), for
//                                    studies/convergence/plot_convergence.py.
TEST(SphericalWave, DISABLED_ConvergenceStudy) {
  const char* prefix = std::getenv("SPHERICAL_WAVE_CSV");
  const char* start = std::getenv("SPHERICAL_WAVE_CT0");  // e.g. 1.2: outgoing start
  const double ct0 = start ? std::atof(start) : 0.0;
  const Transfer transfer = transfer_from_environment();
  const std::vector<int> cells = cells_from_environment({4, 6, 8, 12, 16});
  const char* study_csv = std::getenv("SPHERICAL_WAVE_STUDY_CSV");
  std::cout << "transfer " << transfer.suffix() << " (empty: FLIP)\n";
  for (const int n : cells) {
    const auto t_start = std::chrono::steady_clock::now();
    const std::clock_t c_start = std::clock();
    const WaveErrors e = run_spherical_wave(n, 2.5, ct0, transfer);
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    // Process CPU time: on a shared machine with one thread (OMP_NUM_THREADS=1) it is the run's
    // cost, where the wall time also counts the other processes.
    const double cpu = static_cast<double>(std::clock() - c_start) / CLOCKS_PER_SEC;
    print("study", n, e);
    std::cout << "  wall " << wall << " s, CPU " << cpu << " s\n";
    if (study_csv != nullptr) {
      const bool fresh = !std::ifstream(study_csv).good();
      std::ofstream out(study_csv, std::ios::app);
      ASSERT_TRUE(out) << "SPHERICAL_WAVE_STUDY_CSV: cannot write " << study_csv;
      if (fresh) out << "problem,shape,cells,h_m,error,wall_s,steps,particles\n";
      out.precision(9);
      out << "spherical_wave_srr" << (ct0 > 0.0 ? "_outgoing" : "") << transfer.suffix()
          << ",ugimp," << n << "," << kA / n << "," << e.srr_l2 << "," << cpu << "," << e.steps
          << "," << e.points << "\n";
    }
    if (prefix == nullptr) continue;
    std::ofstream csv(std::string(prefix) + std::to_string(n) + ".csv");
    csv << "r_m,srr_mpm_Pa,srr_exact_Pa,stt_mpm_Pa,stt_exact_Pa,vr_mpm_m_per_s,vr_exact_m_per_s\n";
    for (const auto& row : e.profile) {
      for (std::size_t k = 0; k < row.size(); ++k) csv << (k ? "," : "") << row[k];
      csv << "\n";
    }
  }
}
