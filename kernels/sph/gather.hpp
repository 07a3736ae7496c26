#pragma once
// The two gather passes of the SPH step (DESIGN.md "The SPH step", steps 2 and 4): each
// particle sums its own neighbours, in the fixed order of its neighbour list, and writes only
// its own outputs. No scatter, so the result has the same bits on any number of threads.
// Hot loops only: no I/O, no allocation.

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "sph/cubic_spline.hpp"
#include "sph/terms.hpp"

namespace shatter::kernels::sph {

// What both passes read, as column pointers.
struct PairInputs {
  const double* x = nullptr;
  const double* y = nullptr;
  const double* z = nullptr;
  const double* vx = nullptr;
  const double* vy = nullptr;
  const double* vz = nullptr;
  const double* mass = nullptr;
  const double* rho = nullptr;
  const double* h = nullptr;  // smoothing length
  // The smoothing lengths of the lists' criterion |x_i - x_j| < h_i + h_j at these positions,
  // when the lists carry a skin (Verlet lists): entries beyond it are skipped, so the sums are
  // those of a list without the skin. nullptr: every entry counts (the forces pass uses h).
  const double* h_support = nullptr;
};

// True when j is within i's support at the current positions, by the neighbour search's own
// expression (src/sph/neighbours.cpp), so a list with a skin counts exactly the entries a list
// without one holds.
inline bool within_support(const PairInputs& in, const double* h, std::size_t i, std::uint32_t j) {
  const double dx = in.x[i] - in.x[j], dy = in.y[i] - in.y[j], dz = in.z[i] - in.z[j];
  const double reach = h[i] + h[j];
  return dx * dx + dy * dy + dz * dz < reach * reach;
}

// Pass 1 outputs: the increments MaterialModel::update expects (App. A.2 step 7 of the MPM
// paper, same columns as MPM), and rho^{n+1}. L below is the sum of Eq. 18 before the division
// by rho (S^{ab} = sum_j m_j (v_j^a - v_i^a) dW_ij/dx_i^b).
struct RateOutputs {
  double* deps[6] = {};   // xx, yy, zz, xy, yz, xz: eps_dot dt (Eq. 18)
  double* dspin[3] = {};  // xy, yz, xz: omega dt, omega = (L - L^T) / 2
  double* rho = nullptr;  // in: rho^n, out: rho^{n+1}
};

// The kick's viscous heating, made in the same pass (viscous_heating_term). Optional: with
// pair_w == nullptr no heat is computed.
struct KickHeating {
  const double* pair_w = nullptr;  // per list entry, from the force pass (ForceOutputs::pair_w)
  const double* ax = nullptr;      // a^n of the kick
  const double* ay = nullptr;
  const double* az = nullptr;
  double dt_kick = 0.0;
  double* heat = nullptr;  // out: specific heat added over the kick (J/kg)
};

// Pass 1 for particle i (positions x^n, velocities v^{n+1/2}): velocity gradient from Eq. 18
// (its trace is Eq. 16) at the step's midpoint configuration, turned into the strain and spin
// increments over dt and the density rho^{n+1}.
inline void rates_particle(const PairInputs& in, const std::uint32_t* nb, std::size_t count,
                           std::size_t i, double dt, const RateOutputs& out,
                           const KickHeating& kick = {}, std::size_t list_offset = 0) {
  const double xi = in.x[i], yi = in.y[i], zi = in.z[i];
  const double hi = in.h[i];
  const double vi[3] = {in.vx[i], in.vy[i], in.vz[i]};
  const double half_dt = 0.5 * dt;
  double L[3][3] = {};
  double heat = 0.0;
  const double* w = kick.pair_w != nullptr ? kick.pair_w + list_offset : nullptr;
  const double half_kick = 0.5 * kick.dt_kick;
  for (std::size_t k = 0; k < count; ++k) {
    const std::uint32_t j = nb[k];
    if (in.h_support != nullptr && !within_support(in, in.h_support, i, j)) continue;
    const double dv[3] = {in.vx[j] - vi[0], in.vy[j] - vi[1], in.vz[j] - vi[2]};
    if (w != nullptr && w[k] != 0.0) {
      // v_ij at the middle of the kick: v^{n+1/2} - (a_i - a_j) dt_kick / 2.
      const double vm[3] = {-dv[0] - half_kick * (kick.ax[i] - kick.ax[j]),
                            -dv[1] - half_kick * (kick.ay[i] - kick.ay[j]),
                            -dv[2] - half_kick * (kick.az[i] - kick.az[j])};
      const double xij[3] = {xi - in.x[j], yi - in.y[j], zi - in.z[j]};
      viscous_heating_term(heat, w[k], vm, xij);
    }
    // Separation at the midpoint x^{n+1/2} = x^n + v^{n+1/2} dt / 2 of the step the increments
    // cover (midpoint rule: the stress work then matches the leapfrog's kinetic energy change
    // to second order in dt; at x^n it was first order, measured). Pairs that come within
    // reach during the half step are missed, at the kernel's edge where W and dW/dr vanish.
    const double dx[3] = {xi - in.x[j] - half_dt * dv[0], yi - in.y[j] - half_dt * dv[1],
                          zi - in.z[j] - half_dt * dv[2]};
    const double r = std::sqrt(dx[0] * dx[0] + dx[1] * dx[1] + dx[2] * dx[2]);
    const double F = cubic_f(r, 0.5 * (hi + in.h[j]));
    const double grad[3] = {F * dx[0], F * dx[1], F * dx[2]};
    velocity_gradient_term(L, in.mass[j], dv, grad);
  }
  // Eq. 16, forward in time: rho^{n+1} = rho^n - dt sum_j m_j (v_j - v_i) . grad_i W_ij.
  const double rho_new = in.rho[i] - dt * (L[0][0] + L[1][1] + L[2][2]);
  // Eq. 18 divides the sum by rho_i; with rho^{n+1} here, 1 + tr deps = rho^n / rho^{n+1}
  // exactly, which is the density relation MaterialModel::update assumes (it recovers rho^n as
  // rho (1 + tr deps) for its energy update dE = deps : sigma / rho^n). The pair then matches
  // the momentum equation's sigma / rho^2 at both ends of the step, which makes the total energy
  // error second order in dt (with rho^n here it was first order, measured).
  const double k = dt / rho_new;
  out.deps[0][i] = k * L[0][0];
  out.deps[1][i] = k * L[1][1];
  out.deps[2][i] = k * L[2][2];
  out.deps[3][i] = 0.5 * k * (L[0][1] + L[1][0]);
  out.deps[4][i] = 0.5 * k * (L[1][2] + L[2][1]);
  out.deps[5][i] = 0.5 * k * (L[0][2] + L[2][0]);
  out.dspin[0][i] = 0.5 * k * (L[0][1] - L[1][0]);
  out.dspin[1][i] = 0.5 * k * (L[1][2] - L[2][1]);
  out.dspin[2][i] = 0.5 * k * (L[0][2] - L[2][0]);
  out.rho[i] = rho_new;
  if (kick.heat != nullptr) kick.heat[i] = heat * kick.dt_kick;
}

// Pass 2 inputs besides PairInputs.
struct ForceInputs {
  const double* a_stress[6] = {};  // sigma / rho^2 per particle (Voigt), precomputed
  const double* soundspeed = nullptr;
  ViscosityCoefficients viscosity;
  double gravity[3] = {0.0, 0.0, 0.0};
};

struct ForceOutputs {
  double* ax = nullptr;
  double* ay = nullptr;
  double* az = nullptr;
  double* heat = nullptr;    // viscous heating rate at the force's velocities (J/kg/s)
  double* mu = nullptr;      // max_j |mu_ij| (m/s), for the time step
  double* pair_w = nullptr;  // per list entry: m_j Pi_ij F_ij, for viscous_heating_term
};

// Pass 2 for particle i: Eq. 17 with the full stress, Monaghan's viscosity and its heating.
inline void forces_particle(const PairInputs& in, const ForceInputs& f, const std::uint32_t* nb,
                            std::size_t count, std::size_t i, const ForceOutputs& out,
                            std::size_t list_offset = 0) {
  double* w = out.pair_w != nullptr ? out.pair_w + list_offset : nullptr;
  const double xi = in.x[i], yi = in.y[i], zi = in.z[i];
  const double hi = in.h[i], rhoi = in.rho[i], ci = f.soundspeed[i];
  const double vi[3] = {in.vx[i], in.vy[i], in.vz[i]};
  double A_i[6];
  for (int c = 0; c < 6; ++c) A_i[c] = f.a_stress[c][i];
  double acc[3] = {0.0, 0.0, 0.0};
  double heat = 0.0, mu_max = 0.0;
  for (std::size_t k = 0; k < count; ++k) {
    const std::uint32_t j = nb[k];
    const double dx[3] = {xi - in.x[j], yi - in.y[j], zi - in.z[j]};
    const double r2 = dx[0] * dx[0] + dx[1] * dx[1] + dx[2] * dx[2];
    const double reach = hi + in.h[j];
    if (!(r2 < reach * reach)) {  // a skin entry (the search's criterion, same expression)
      if (w != nullptr) w[k] = 0.0;
      continue;
    }
    const double h_ij = 0.5 * (hi + in.h[j]);
    const double F = cubic_f(std::sqrt(r2), h_ij);
    const double grad[3] = {F * dx[0], F * dx[1], F * dx[2]};
    const double A_j[6] = {f.a_stress[0][j], f.a_stress[1][j], f.a_stress[2][j],
                           f.a_stress[3][j], f.a_stress[4][j], f.a_stress[5][j]};
    stress_force_term(acc, in.mass[j], A_i, A_j, grad);
    const double vij[3] = {vi[0] - in.vx[j], vi[1] - in.vy[j], vi[2] - in.vz[j]};
    const double vr = vij[0] * dx[0] + vij[1] * dx[1] + vij[2] * dx[2];
    const ViscousPair q = monaghan_viscosity(
        f.viscosity, vr, r2, h_ij, 0.5 * (ci + f.soundspeed[j]), 0.5 * (rhoi + in.rho[j]));
    if (q.pi != 0.0) {
      viscous_term(acc, heat, in.mass[j], q.pi, vij, grad);
      mu_max = std::fmax(mu_max, -q.mu);
    }
    if (w != nullptr) w[k] = in.mass[j] * q.pi * F;
  }
  out.ax[i] = acc[0] + f.gravity[0];
  out.ay[i] = acc[1] + f.gravity[1];
  out.az[i] = acc[2] + f.gravity[2];
  out.heat[i] = heat;
  out.mu[i] = mu_max;
}

}  // namespace shatter::kernels::sph
