#pragma once
// The spherically diverging elastic wave of docs/verification.md ("Spherical elastic wave"): its
// exact solution, the octant's initial state and the error measures, shared by the MPM test
// (tests/verification/mpm/spherical_wave_test.cpp, which derives the solution) and the SPH test
// (tests/verification/sph/spherical_wave_test.cpp), so that both methods are measured by the same
// code and only the solver differs. "h" is the MPM cell a / cells_per_a; the points sit
// 2 x 2 x 2 per cell (spacing h / 2) in the octant of a ball of radius 4 a.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "shatter/core/config.hpp"
#include "shatter/core/particles.hpp"
#include "support/lattice.hpp"

namespace shatter::test::spherical_wave {

using Eigen::Vector3d;

constexpr double kRho = 2700.0, kYoung = 53.1e9, kPoisson = 0.15;
constexpr double kA = 0.1;  // m, radius of the initial velocity bump
// Potential amplitude (m^2/s); negative: the initial velocity points outwards, peak 0.86 m/s, so
// strains stay ~2e-4 and the geometric non-linearity of the updated-Lagrangian step is ~1e-4.
constexpr double kPsi = -0.05;

struct Exact {
  double ur, vr, srr, stt;
};

struct Elastic {
  double lambda, G, M, c;
  Elastic() {
    G = kYoung / (2.0 * (1.0 + kPoisson));
    const double K = kYoung / (3.0 * (1.0 - 2.0 * kPoisson));
    lambda = K - 2.0 * G / 3.0;
    M = lambda + 2.0 * G;
    c = std::sqrt(M / kRho);
  }
};

// n-th derivative of F(s) = k (1 - s^2/a^2)^4 on |s| < a (zero outside), k = A a^2 / (16 c).
inline double F(double s, int n, double c) {
  if (std::abs(s) >= kA) return 0.0;
  const double k = kPsi * kA * kA / (16.0 * c);
  const double a2 = kA * kA, q = s * s / a2, one = 1.0 - q;
  switch (n) {
    case 0:
      return k * one * one * one * one;
    case 1:
      return k * (-8.0 * s / a2) * one * one * one;
    default:
      return k * (-8.0 / a2) * one * one * (1.0 - 7.0 * q);
  }
}

// Eqs. (1), (2) and u, v at radius r > 0, time t.
inline Exact exact(const Elastic& m, double r, double t) {
  const double c = m.c, sm = r - c * t, sp = r + c * t;
  const double w = F(sm, 0, c) - F(sp, 0, c);
  const double wr = F(sm, 1, c) - F(sp, 1, c);
  const double wrr = F(sm, 2, c) - F(sp, 2, c);
  const double wt = -c * (F(sm, 1, c) + F(sp, 1, c));
  const double wrt = -c * (F(sm, 2, c) + F(sp, 2, c));
  const double near = wr / (r * r) - w / (r * r * r);  // u_r / r
  return {wr / r - w / (r * r), wrt / r - wt / (r * r), m.M * wrr / r - 4.0 * m.G * near,
          m.lambda * wrr / r + 2.0 * m.G * near};
}

// v0 = grad(psi0) = psi0'(r) x / r = -6 A / a^2 (1 - r^2/a^2)^2 x.
inline Vector3d initial_velocity(const Vector3d& x) {
  const double q = x.squaredNorm() / (kA * kA);
  if (q >= 1.0) return Vector3d::Zero();
  return (-6.0 * kPsi / (kA * kA) * (1.0 - q) * (1.0 - q)) * x;
}

struct WaveErrors {
  double peak = 0;                                // max |s_rr| of the exact pulse (Pa): the scale
  double srr_l2 = 0, srr_max = 0;                 // point-wise, relative to `peak`
  double stt_l2 = 0, stt_max = 0;                 //
  double v_l2 = 0, v_max = 0;                     // relative to the exact max |v_r|
  double srr_shell_l2 = 0, stt_shell_l2 = 0;      // shell (width h) means against exact shell means
  double srr_noise = 0, stt_noise = 0;            // RMS of the point error about its shell mean
  double stt_tension = 0, stt_tension_exact = 0;  // largest hoop tension, shell means (Pa)
  double srr_tension = 0, srr_tension_exact = 0;  // largest radial tension, shell means (Pa)
  double stt_tension_points = 0;                  // largest hoop tension of any point (Pa)
  double tangential_l2 = 0;  // |s_t1 - s_t2| and shear, which must vanish, relative
  std::size_t points = 0, sampled = 0;
  std::uint64_t steps = 0;
  // Per shell: mean radius, MPM and exact means of s_rr, s_tt, v_r (for the study's plots).
  std::vector<std::array<double, 7>> profile;
};

inline double sq(double x) {
  return x * x;
}

// The octant's points at h = a / cells_per_a. ct0_over_a > 0 starts from the exact state at
// c t0 = ct0_over_a a instead of t = 0 (stress and velocity set on the points, displacement
// ignored: it is O(strain)); with ct0 >= a the wave is then purely outgoing and never focuses at
// the centre.
inline ParticleStore make_octant(int cells_per_a, double ct0_over_a) {
  const Elastic m;
  const double h = kA / cells_per_a, R = 4.0 * kA;
  const double t0 = ct0_over_a * kA / m.c;
  ParticleStore s;
  const Range all = test::add_lattice(
      s, 0, Vector3d::Zero(), Vector3d::Constant(R), h / 2, kRho,
      [&](const Vector3d& x) { return x.norm() <= R; },
      [&](const Vector3d& x) -> Vector3d {
        if (t0 == 0.0) return initial_velocity(x);
        return exact(m, x.norm(), t0).vr * x.normalized();
      });
  if (t0 > 0.0) {
    s.require({Field::sxx, Field::syy, Field::szz, Field::sxy, Field::syz, Field::sxz});
    for (std::size_t p = all.begin; p < all.end; ++p) {
      const Vector3d x(s.col(Field::x)[p], s.col(Field::y)[p], s.col(Field::z)[p]);
      const Exact ex = exact(m, x.norm(), t0);
      const Vector3d n = x.normalized();
      const Eigen::Matrix3d sig =
          ex.stt * Eigen::Matrix3d::Identity() + (ex.srr - ex.stt) * (n * n.transpose());
      s.col(Field::sxx)[p] = sig(0, 0);
      s.col(Field::syy)[p] = sig(1, 1);
      s.col(Field::szz)[p] = sig(2, 2);
      s.col(Field::sxy)[p] = sig(0, 1);
      s.col(Field::syz)[p] = sig(1, 2);
      s.col(Field::sxz)[p] = sig(0, 2);
    }
  }
  return s;
}

// The octant's solver settings: cell h = a / cells_per_a (the MPM grid; SPH takes only the
// domain), symmetry planes x = y = z = 0, the other faces free.
inline SolverConfig octant_config(int cells_per_a) {
  SolverConfig cfg;
  cfg.cell_size = kA / cells_per_a;
  cfg.domain.lo = Vector3d::Zero();
  cfg.domain.faces = {BoundaryKind::symmetry, BoundaryKind::none,     BoundaryKind::symmetry,
                      BoundaryKind::none,     BoundaryKind::symmetry, BoundaryKind::none};
  return cfg;
}

// Compares every point of P whose radius lies within the pulse's support at c t = ct_over_a a,
// widened by 2 h (the grid smears the edges over ~2 cells), with the exact solution: stresses at
// t, velocities at t_v (the leapfrog's v^{n+1/2}). `steps` is the solver's step count.
inline WaveErrors measure(const ParticleStore& P, int cells_per_a, double ct_over_a, double t_v,
                          std::uint64_t steps) {
  const Elastic m;
  const double h = kA / cells_per_a;
  const double t = ct_over_a * kA / m.c;
  WaveErrors e;
  e.steps = steps;
  double vpeak = 0;
  for (int k = 0; k <= 4000; ++k) {
    const double r = (ct_over_a - 1.0) * kA + 2.0 * kA * k / 4000.0;
    e.peak = std::max(e.peak, std::abs(exact(m, r, t).srr));
    vpeak = std::max(vpeak, std::abs(exact(m, r, t_v).vr));
  }
  const double r_lo = (ct_over_a - 1.0) * kA - 2 * h, r_hi = (ct_over_a + 1.0) * kA + 2 * h;
  const auto n_shells = static_cast<std::size_t>(std::ceil((r_hi - r_lo) / h));
  // Per shell: count, sum of (MPM - exact) for s_rr, s_tt; sums of MPM and exact values.
  std::vector<double> cnt(n_shells), drr(n_shells), dtt(n_shells), mrr(n_shells), mtt(n_shells),
      xrr(n_shells), xtt(n_shells), rad(n_shells), mv(n_shells), xv(n_shells);
  struct Sample {
    std::size_t shell;
    double err_rr, err_tt;
  };
  std::vector<Sample> samples;
  e.points = P.size();
  for (std::size_t p = 0; p < P.size(); ++p) {
    const Vector3d x(P.col(Field::x)[p], P.col(Field::y)[p], P.col(Field::z)[p]);
    const double r = x.norm();
    if (r < r_lo || r > r_hi) continue;
    const Vector3d n = x / r;
    Eigen::Matrix3d sig;
    sig << P.col(Field::sxx)[p], P.col(Field::sxy)[p], P.col(Field::sxz)[p], P.col(Field::sxy)[p],
        P.col(Field::syy)[p], P.col(Field::syz)[p], P.col(Field::sxz)[p], P.col(Field::syz)[p],
        P.col(Field::szz)[p];
    const double srr = n.dot(sig * n);
    const double stt = 0.5 * (sig.trace() - srr);  // mean of the two tangential normal stresses
    // Deviation from the spherically symmetric form diag(s_rr, s_tt, s_tt) in the local frame.
    const Eigen::Matrix3d sym =
        stt * Eigen::Matrix3d::Identity() + (srr - stt) * (n * n.transpose());
    const Exact ex = exact(m, r, t);
    const double vr =
        Vector3d(P.col(Field::vx)[p], P.col(Field::vy)[p], P.col(Field::vz)[p]).dot(n);
    const double ev = exact(m, r, t_v).vr;
    const double err_rr = srr - ex.srr, err_tt = stt - ex.stt;
    e.srr_l2 += sq(err_rr);
    e.stt_l2 += sq(err_tt);
    e.v_l2 += sq(vr - ev);
    e.srr_max = std::max(e.srr_max, std::abs(err_rr));
    e.stt_max = std::max(e.stt_max, std::abs(err_tt));
    e.v_max = std::max(e.v_max, std::abs(vr - ev));
    e.tangential_l2 += (sig - sym).squaredNorm();
    e.stt_tension_points = std::max(e.stt_tension_points, stt);
    const auto k = std::min(n_shells - 1, static_cast<std::size_t>((r - r_lo) / h));
    cnt[k] += 1;
    drr[k] += err_rr;
    dtt[k] += err_tt;
    mrr[k] += srr;
    mtt[k] += stt;
    xrr[k] += ex.srr;
    xtt[k] += ex.stt;
    rad[k] += r;
    mv[k] += vr;
    xv[k] += ev;
    samples.push_back({k, err_rr, err_tt});
  }
  e.sampled = samples.size();
  const double N = static_cast<double>(e.sampled);
  // Equal point volumes, so the point mean is the volume-weighted L2 norm over the shell region.
  e.srr_l2 = std::sqrt(e.srr_l2 / N) / e.peak;
  e.stt_l2 = std::sqrt(e.stt_l2 / N) / e.peak;
  e.v_l2 = std::sqrt(e.v_l2 / N) / vpeak;
  e.srr_max /= e.peak;
  e.stt_max /= e.peak;
  e.v_max /= vpeak;
  e.tangential_l2 = std::sqrt(e.tangential_l2 / N) / e.peak;
  double shell_rr = 0, shell_tt = 0;
  for (std::size_t k = 0; k < n_shells; ++k) {
    if (cnt[k] == 0) continue;
    shell_rr += cnt[k] * sq(drr[k] / cnt[k]);
    shell_tt += cnt[k] * sq(dtt[k] / cnt[k]);
    e.stt_tension = std::max(e.stt_tension, mtt[k] / cnt[k]);
    e.stt_tension_exact = std::max(e.stt_tension_exact, xtt[k] / cnt[k]);
    e.srr_tension = std::max(e.srr_tension, mrr[k] / cnt[k]);
    e.srr_tension_exact = std::max(e.srr_tension_exact, xrr[k] / cnt[k]);
    e.profile.push_back({rad[k] / cnt[k], mrr[k] / cnt[k], xrr[k] / cnt[k], mtt[k] / cnt[k],
                         xtt[k] / cnt[k], mv[k] / cnt[k], xv[k] / cnt[k]});
  }
  e.srr_shell_l2 = std::sqrt(shell_rr / N) / e.peak;
  e.stt_shell_l2 = std::sqrt(shell_tt / N) / e.peak;
  // Grid-scale noise: the part of each point's error that is not a smooth function of r.
  for (const Sample& q : samples) {
    e.srr_noise += sq(q.err_rr - drr[q.shell] / cnt[q.shell]);
    e.stt_noise += sq(q.err_tt - dtt[q.shell] / cnt[q.shell]);
  }
  e.srr_noise = std::sqrt(e.srr_noise / N) / e.peak;
  e.stt_noise = std::sqrt(e.stt_noise / N) / e.peak;
  return e;
}

inline void print(const char* label, int cells_per_a, const WaveErrors& e) {
  std::cout << label << " a/h=" << cells_per_a << " points=" << e.points << " sampled=" << e.sampled
            << " steps=" << e.steps << " peak|s_rr|=" << e.peak << " Pa\n  s_rr L2 " << e.srr_l2
            << " max " << e.srr_max << " | s_tt L2 " << e.stt_l2 << " max " << e.stt_max
            << " | v_r L2 " << e.v_l2 << " max " << e.v_max << "\n  shell-mean L2 s_rr "
            << e.srr_shell_l2 << " s_tt " << e.stt_shell_l2 << " | noise s_rr " << e.srr_noise
            << " s_tt " << e.stt_noise << " | non-spherical part " << e.tangential_l2
            << "\n  hoop tension (shell mean) " << e.stt_tension << " exact " << e.stt_tension_exact
            << " (any point " << e.stt_tension_points << ") | radial tension " << e.srr_tension
            << " exact " << e.srr_tension_exact << "\n";
}

}  // namespace shatter::test::spherical_wave
