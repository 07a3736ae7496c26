// Particle-grid velocity transfers (issue 16): XPIC(m) (Hammerquist & Nairn 2017) and the FLIP/PIC
// blend (SolverConfig::pic_fraction), checked against their definitions rather than against
// earlier runs: XPIC's particle update against a dense-matrix evaluation of
// v_p <- S V*_m = (I - (I - S S+)^m) v_p, XPIC(1) against PIC bitwise, the blend's linearity in
// the fraction, momentum to round-off, rigid translation exactly. Bad settings are refused by the
// scene, naming the key and line (tests/unit/scene/transfer_keys_test.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "mpm/shape.hpp"
#include "shatter/material/linear_elastic.hpp"
#include "shatter/mpm/simulation.hpp"
#include "support/lattice.hpp"

using namespace shatter;
using Eigen::Vector3d;

namespace {

constexpr double kCell = 0.1;

std::vector<MaterialPtr> elastic() {
  return {std::make_shared<LinearElastic>(1000.0, 1e5, 0.3)};
}

// `order` is XPIC's m or FMPM's k, whichever the transfer reads.
SolverConfig config(TransferKind transfer, double pic_fraction = 0.0, int order = 5) {
  SolverConfig cfg;
  cfg.shape = ShapeKind::ugimp;
  cfg.transfer = transfer;
  cfg.pic_fraction = pic_fraction;
  cfg.xpic_order = order;
  cfg.fmpm_order = order;
  cfg.cell_size = kCell;
  return cfg;
}

// A 3 x 3 x 3 cell block, 2 x 2 x 2 points per cell, with a velocity that is pure grid-scale noise
// plus a smooth part (deterministic, no RNG), and optionally a stress field that varies in space.
ParticleStore noisy_block(bool stressed) {
  ParticleStore s;
  test::add_lattice(
      s, 0, Vector3d::Zero(), Vector3d::Constant(3 * kCell), 0.5 * kCell, 1000.0,
      [](const Vector3d&) { return true; },
      [](const Vector3d& x) {
        const double k = 2.0 * M_PI / kCell;  // alternates sign between neighbouring points
        // sin(k x) = +-1 at the cell-centred lattice sites, alternating point to point
        return Vector3d(0.3 + std::sin(k * x.x()) * std::sin(k * x.y()),
                        -0.2 + std::sin(7.0 * x.z()), 0.1 * std::sin(k * x.z()) + x.x());
      });
  if (stressed) {
    s.require(kStress);
    for (std::size_t p = 0; p < s.size(); ++p) {
      const double x = s.col(Field::x)[p], y = s.col(Field::y)[p], z = s.col(Field::z)[p];
      s.col(Field::sxx)[p] = 1e3 * std::sin(11.0 * x + 3.0 * y);
      s.col(Field::syy)[p] = -2e3 * std::cos(5.0 * z);
      s.col(Field::sxy)[p] = 5e2 * x * y;
    }
  }
  return s;
}

// Particle velocities after `steps` steps, indexed by particle id (the sort permutes the columns).
std::vector<Vector3d> velocities_by_id(const ParticleStore& s) {
  std::vector<Vector3d> v(s.size());
  const auto id = s.col(IField::id);
  for (std::size_t p = 0; p < s.size(); ++p) {
    v[static_cast<std::size_t>(id[p])] =
        Vector3d(s.col(Field::vx)[p], s.col(Field::vy)[p], s.col(Field::vz)[p]);
  }
  return v;
}

std::vector<Vector3d> step_once(const ParticleStore& start, const SolverConfig& cfg) {
  Simulation sim(cfg, start, elastic(), 1);
  sim.step();
  return velocities_by_id(sim.particles());
}

// 1D uGIMP weights of every node a particle at x reaches, as the engine's Stencil forms them.
std::vector<std::pair<std::int64_t, double>> weights_1d(double x, double size0) {
  double w[3], dw[3];
  const double lp = std::min(0.5 * size0 / kCell, 0.5);
  const std::int64_t first = kernels::GimpShape::weights(x, 1.0 / kCell, lp, w, dw);
  return {{first, w[0]}, {first + 1, w[1]}, {first + 2, w[2]}};
}

// A stressed, colliding pair of elastic spheres after 60 steps (the order-one identities below).
std::unique_ptr<Simulation> colliding_pair(const SolverConfig& cfg) {
  ParticleStore s;
  test::add_sphere(s, 0, Vector3d(0.2, 0.2, 0.2), 0.2, 0.05, 1000.0, Vector3d(1, 1, 0.5), 0);
  test::add_sphere(s, 0, Vector3d(0.62, 0.62, 0.4), 0.2, 0.05, 1000.0, Vector3d(-1, -1, 0), 1);
  auto sim = std::make_unique<Simulation>(cfg, std::move(s), elastic(), 1);
  for (int k = 0; k < 60; ++k) sim->step();
  return sim;
}

}  // namespace

// XPIC(m) against its definition. With no stress and no body force the grid acceleration is
// exactly zero in the first step, so the particle velocity after it is S V*_m = P_m v_p with
// P_m = I - (I - S S+)^m (Hammerquist & Nairn 2017), S_pI = N_I(x_p) and
// S+ = diag(1/m_I) S^T diag(m_p). Evaluated here with dense matrices, independently of the
// engine's recursion, passes and scatter. Tolerance 1e-12 of the largest velocity: round-off of
// a few hundred terms per sum (measured up to ~2e-15); a wrong binomial weight, sign or missing
// pass changes the result by 1e-2 or more (the noise is removed to different degrees for each m).
TEST(Xpic, FirstStepEqualsTheDenseProjection) {
  const ParticleStore start = noisy_block(false);
  const std::size_t n = start.size();
  // Dense S over the nodes the particles reach.
  std::map<std::tuple<std::int64_t, std::int64_t, std::int64_t>, int> node_index;
  std::vector<std::vector<std::pair<int, double>>> rows(n);
  const auto id = start.col(IField::id);
  for (std::size_t p = 0; p < n; ++p) {
    const double s0 = start.col(Field::size0)[p];
    const auto wx = weights_1d(start.col(Field::x)[p], s0);
    const auto wy = weights_1d(start.col(Field::y)[p], s0);
    const auto wz = weights_1d(start.col(Field::z)[p], s0);
    for (const auto& [i, a] : wx) {
      for (const auto& [j, b] : wy) {
        for (const auto& [k, c] : wz) {
          const auto key = std::tuple{i, j, k};
          const auto it = node_index.emplace(key, static_cast<int>(node_index.size())).first;
          rows[static_cast<std::size_t>(id[p])].push_back({it->second, a * b * c});
        }
      }
    }
  }
  // S+ w = diag(1/m_I) S^T diag(m_p) w and S V, as plain loops over the rows of S.
  const std::size_t nn = node_index.size();
  std::vector<double> mp(n), mi(nn, 0.0);
  std::vector<Vector3d> v0(n);
  for (std::size_t p = 0; p < n; ++p) {
    const auto q = static_cast<std::size_t>(id[p]);
    mp[q] = start.col(Field::mass)[p];
    v0[q] = Vector3d(start.col(Field::vx)[p], start.col(Field::vy)[p], start.col(Field::vz)[p]);
  }
  for (std::size_t p = 0; p < n; ++p) {
    for (const auto& [i, w] : rows[p]) mi[static_cast<std::size_t>(i)] += mp[p] * w;
  }
  const double empty = 1e-12 * *std::min_element(mp.begin(), mp.end());  // the engine's
  auto s_splus = [&](const std::vector<Vector3d>& w) {                   // S S+ w
    std::vector<Vector3d> V(nn, Vector3d::Zero());
    for (std::size_t p = 0; p < n; ++p) {
      for (const auto& [i, a] : rows[p]) V[static_cast<std::size_t>(i)] += mp[p] * a * w[p];
    }
    for (std::size_t i = 0; i < nn; ++i)
      V[i] = mi[i] > empty ? Vector3d(V[i] / mi[i]) : Vector3d::Zero();
    std::vector<Vector3d> out(n, Vector3d::Zero());
    for (std::size_t p = 0; p < n; ++p) {
      for (const auto& [i, a] : rows[p]) out[p] += a * V[static_cast<std::size_t>(i)];
    }
    return out;
  };

  double vmax = 0.0;
  for (const Vector3d& v : v0) vmax = std::max(vmax, v.cwiseAbs().maxCoeff());
  for (const int m : {1, 2, 3, 5}) {
    // r = (I - S S+)^m v0; expected = v0 - r
    std::vector<Vector3d> r = v0;
    for (int k = 0; k < m; ++k) {
      const auto a = s_splus(r);
      for (std::size_t p = 0; p < n; ++p) r[p] -= a[p];
    }
    // FMPM(k) gives S sum_{i<k} (I - S+ S)^i S+ v0 here (a = 0, so v^{n+1} = V^L = S+ v0),
    // and S (I - S+ S)^i S+ = (I - S S+)^i S S+, so the sum telescopes to the same P_k v0:
    // FMPM's nested (Neumann) summation is checked against the dense projection too.
    for (const TransferKind t : {TransferKind::xpic, TransferKind::fmpm}) {
      const auto got = step_once(start, config(t, 0.0, m));
      double worst = 0.0, removed = 0.0;
      for (std::size_t p = 0; p < n; ++p) {
        worst = std::max(worst, (got[p] - (v0[p] - r[p])).cwiseAbs().maxCoeff());
        removed = std::max(removed, r[p].cwiseAbs().maxCoeff());
      }
      EXPECT_LT(worst, 1e-12 * vmax) << name_of(t) << "(" << m << ")";
      // The filter did something: the noise is gone to a degree that depends on m.
      EXPECT_GT(removed, 1e-2 * vmax) << name_of(t) << "(" << m << ")";
    }
  }
}

// XPIC(1) is PIC (Hammerquist & Nairn 2017): the engine takes the same branch, so the two agree
// bitwise over many steps of a stressed, colliding pair.
TEST(Xpic, OrderOneIsPicBitwise) {
  const auto xpic = colliding_pair(config(TransferKind::xpic, 0.0, 1));
  const auto pic = colliding_pair(config(TransferKind::flip, 1.0));
  const auto flip = colliding_pair(config(TransferKind::flip));
  for (const Field f : {Field::x, Field::vx, Field::vy, Field::sxx, Field::rho}) {
    const auto a = xpic->particles().col(f), b = pic->particles().col(f);
    EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size_bytes()), 0) << name_of(f);
  }
  EXPECT_EQ(xpic->energy().kinetic, pic->energy().kinetic);
  // ... and not FLIP: PIC dissipates.
  EXPECT_LT(pic->energy().kinetic, flip->energy().kinetic);
  EXPECT_GT(test::max_abs_stress(pic->particles()), 1.0);
}

// FMPM(1) is PIC: v_F = M_L^{-1} p^{n+1} = v^{n+1}, no pass runs, and the particle takes
// S v^{n+1} and moves by S v^{n+1} dt, which is the pic_fraction = 1 update; bitwise over 60
// steps of a stressed, colliding pair.
TEST(Fmpm, OrderOneIsPicBitwise) {
  const auto fmpm = colliding_pair(config(TransferKind::fmpm, 0.0, 1));
  const auto pic = colliding_pair(config(TransferKind::flip, 1.0));
  for (const Field f : {Field::x, Field::vx, Field::vy, Field::sxx, Field::rho}) {
    const auto a = fmpm->particles().col(f), b = pic->particles().col(f);
    EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size_bytes()), 0) << name_of(f);
  }
  EXPECT_EQ(fmpm->energy().kinetic, pic->energy().kinetic);
  EXPECT_GT(test::max_abs_stress(pic->particles()), 1.0);
}

// FMPM filters the force term too, XPIC does not: from rest (v_p = 0, so V^L = 0) under a
// stress field, XPIC(k) gives S (0 + a dt), which is the PIC and the FLIP step, while FMPM(k)
// gives S v_F with v_F the series applied to a dt. Tolerances: XPIC against PIC 1e-13 of the
// largest velocity (round-off of k - 1 passes applied to zero: exactly zero); FMPM(3) against
// PIC more than 1e-3 of it (the series changes the grid-scale part of a dt by O(1) on this
// stress field; measured below).
TEST(Fmpm, FiltersTheForceTermWhereXpicDoesNot) {
  ParticleStore start = noisy_block(true);
  for (std::size_t p = 0; p < start.size(); ++p) {
    start.col(Field::vx)[p] = start.col(Field::vy)[p] = start.col(Field::vz)[p] = 0.0;
  }
  const auto pic = step_once(start, config(TransferKind::flip, 1.0));
  const auto xpic = step_once(start, config(TransferKind::xpic, 0.0, 3));
  const auto fmpm = step_once(start, config(TransferKind::fmpm, 0.0, 3));
  double vmax = 0.0, x_off = 0.0, f_off = 0.0;
  for (std::size_t p = 0; p < pic.size(); ++p) {
    vmax = std::max(vmax, pic[p].cwiseAbs().maxCoeff());
    x_off = std::max(x_off, (xpic[p] - pic[p]).cwiseAbs().maxCoeff());
    f_off = std::max(f_off, (fmpm[p] - pic[p]).cwiseAbs().maxCoeff());
  }
  ASSERT_GT(vmax, 0.0);
  EXPECT_LT(x_off, 1e-13 * vmax);
  EXPECT_GT(f_off, 1e-3 * vmax);
}

// The blend v <- (1 - f) (v + S a dt) + f S v^{n+1} is linear in f: one step from a stressed,
// noisy state (grid acceleration non-zero) with f = 0.3 equals 0.7 x the f = 0 step plus 0.3 x the
// f = 1 step. Tolerance 1e-13 of the largest velocity (round-off of one blend; measured ~1e-16).
// f = 0 is FLIP by an exact branch in the kernel (no arithmetic on the PIC term at all).
TEST(PicFraction, OneStepIsTheStatedBlendOfFlipAndPic) {
  const ParticleStore start = noisy_block(true);
  const auto flip = step_once(start, config(TransferKind::flip, 0.0));
  const auto pic = step_once(start, config(TransferKind::flip, 1.0));
  const auto mix = step_once(start, config(TransferKind::flip, 0.3));
  double vmax = 0.0, worst = 0.0, spread = 0.0;
  for (std::size_t p = 0; p < mix.size(); ++p) {
    vmax = std::max(vmax, flip[p].cwiseAbs().maxCoeff());
    worst = std::max(worst, (mix[p] - (0.7 * flip[p] + 0.3 * pic[p])).cwiseAbs().maxCoeff());
    spread = std::max(spread, (flip[p] - pic[p]).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 1e-13 * vmax);
  EXPECT_GT(spread, 1e-2 * vmax);  // FLIP and PIC differ here, so the check has teeth
}

// Total momentum is kept by every scheme: sum_p m_p S V = sum_I m_I V_I, and each S+ S pass keeps
// the mass-weighted sum (partition of unity), so XPIC's V*_m carries the momentum of V^L
// (sum_k (-1)^{k+1} C(m,k) = 1). Two spheres collide (stress, cell crossings, no walls) for 60
// steps. Tolerance 1e-12 of sum m|v|: round-off (measured <= 1e-15); a weight not summing to one
// moves it by O(1).
TEST(Transfers, KeepMomentumToRoundOff) {
  for (const auto& [transfer, f, m] :
       {std::tuple{TransferKind::flip, 0.3, 5}, std::tuple{TransferKind::xpic, 0.0, 2},
        std::tuple{TransferKind::xpic, 0.0, 4}, std::tuple{TransferKind::fmpm, 0.0, 2},
        std::tuple{TransferKind::fmpm, 0.0, 5}}) {
    ParticleStore s;
    test::add_sphere(s, 0, Vector3d(0.2, 0.2, 0.2), 0.2, 0.05, 1000.0, Vector3d(1, 1, 0.5), 0);
    test::add_sphere(s, 0, Vector3d(0.62, 0.62, 0.4), 0.2, 0.05, 1000.0, Vector3d(-1, -1, 0), 1);
    auto momentum = [](const ParticleStore& q, double* scale) {
      Vector3d P = Vector3d::Zero();
      *scale = 0.0;
      for (std::size_t p = 0; p < q.size(); ++p) {
        const Vector3d v(q.col(Field::vx)[p], q.col(Field::vy)[p], q.col(Field::vz)[p]);
        P += q.col(Field::mass)[p] * v;
        *scale += q.col(Field::mass)[p] * v.norm();
      }
      return P;
    };
    double scale = 0.0, unused = 0.0;
    const Vector3d P0 = momentum(s, &scale);
    Simulation sim(config(transfer, f, m), std::move(s), elastic(), 1);
    for (int k = 0; k < 60; ++k) sim.step();
    const Vector3d P1 = momentum(sim.particles(), &unused);
    EXPECT_LT((P1 - P0).norm(), 1e-12 * scale) << name_of(transfer) << " " << f << " " << m;
    EXPECT_GT(test::max_abs_stress(sim.particles()), 1.0);  // they did collide
  }
}

// A body in uniform motion stays in uniform motion: the grid represents a constant field exactly,
// S+ S u = u, so no filter may change it. 40 steps, every particle's velocity within 1e-13 of u
// (round-off; the strain rate of a constant field is zero to round-off, so no stress develops).
TEST(Transfers, RigidTranslationIsTransportedExactly) {
  const Vector3d u(0.3, -0.2, 0.1);
  for (const auto& [transfer, f, m] :
       {std::tuple{TransferKind::flip, 0.3, 5}, std::tuple{TransferKind::flip, 1.0, 5},
        std::tuple{TransferKind::xpic, 0.0, 3}, std::tuple{TransferKind::fmpm, 0.0, 3},
        std::tuple{TransferKind::fmpm, 0.0, 10}}) {
    ParticleStore s;
    test::add_sphere(s, 0, Vector3d(0.2, 0.2, 0.2), 0.2, 0.05, 1000.0, u, 0);
    Simulation sim(config(transfer, f, m), std::move(s), elastic(), 1);
    for (int k = 0; k < 40; ++k) sim.step();
    double worst = 0.0;
    for (const Vector3d& v : velocities_by_id(sim.particles())) {
      worst = std::max(worst, (v - u).cwiseAbs().maxCoeff());
    }
    EXPECT_LT(worst, 1e-13) << name_of(transfer) << " " << f << " " << m;
  }
}
