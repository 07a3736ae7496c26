#pragma once
// The SPH equations of Benz & Asphaug (1995, Sec. 4.1) as a short list of named pair terms
// (STYLE.md "SPH physics as named terms"). Each term is what neighbour j adds to particle i's
// sum; the gather passes (kernels/sph/gather.hpp) call them in a fixed order, with no virtual
// call per pair. grad is grad_i W_ij = F(r_ij, h_ij) (x_i - x_j), h_ij = (h_i + h_j) / 2
// (BA95 after Eq. 16), so grad_j W_ji = -grad_i W_ij bitwise and the pair forces are equal and
// opposite. The terms are templates over T, double or a SIMD batch (the passes' lanes, one pair
// per lane): the same expressions either way.

#include <cmath>

#include "constitutive/simd.hpp"

namespace shatter::kernels::sph {

// Velocity gradient, the sum behind Eqs. 16 and 18:
//   rho_i L_i^{ab} = sum_j m_j (v_j^a - v_i^a) dW_ij/dx_i^b.
// Eq. 18 is its symmetric part (strain rate), the rotation rate (Eq. 7) its skew part, and
// Eq. 16 is its trace: drho_i/dt = -sum_j m_j (v_j - v_i) . grad_i W_ij = -rho_i tr L_i.
// dv = v_j - v_i.
template <class T>
inline void velocity_gradient_term(T (&L)[3][3], const T& m_j, const T (&dv)[3],
                                   const T (&grad)[3]) {
  for (int a = 0; a < 3; ++a) {
    const T w = m_j * dv[a];
    for (int b = 0; b < 3; ++b) L[a][b] += w * grad[b];
  }
}

// Pressure and stress force, Eq. 17 (the symmetric form, full Cauchy stress sigma = -p I + S,
// damage included): dv_i^a/dt += m_j (sigma_i^{ab} / rho_i^2 + sigma_j^{ab} / rho_j^2) dW/dx_i^b.
// A = sigma / rho^2 in Voigt order xx, yy, zz, xy, yz, xz.
template <class T>
inline void stress_force_term(T (&acc)[3], const T& m_j, const T (&A_i)[6], const T (&A_j)[6],
                              const T (&grad)[3]) {
  const T s[6] = {A_i[0] + A_j[0], A_i[1] + A_j[1], A_i[2] + A_j[2],
                  A_i[3] + A_j[3], A_i[4] + A_j[4], A_i[5] + A_j[5]};
  acc[0] += m_j * (s[0] * grad[0] + s[3] * grad[1] + s[5] * grad[2]);
  acc[1] += m_j * (s[3] * grad[0] + s[1] * grad[1] + s[4] * grad[2]);
  acc[2] += m_j * (s[5] * grad[0] + s[4] * grad[1] + s[2] * grad[2]);
}

// Monaghan artificial viscosity (Monaghan & Gingold 1983, J. Comput. Phys. 52, 374; the form of
// Monaghan 1992, ARA&A 30, 543, Eq. 4.1, which BA95 call "the usual artificial viscosity"):
//   Pi_ij = (-alpha c_ij mu_ij + beta mu_ij^2) / rho_ij   if v_ij . x_ij < 0, else 0,
//   mu_ij = h_ij v_ij . x_ij / (r_ij^2 + eta^2 h_ij^2),
// with c_ij, rho_ij the pair means, v_ij = v_i - v_j, x_ij = x_i - x_j. Symmetric in i, j.
struct ViscosityCoefficients {
  double alpha = 1.0;  // linear (bulk) term; Monaghan 1992 recommends alpha = 1, beta = 2
  double beta = 2.0;   // quadratic (von Neumann-Richtmyer) term, stops interpenetration
  double eta2 = 0.01;  // eta^2, keeps mu finite as r -> 0
};

struct ViscousPair {
  double pi = 0.0;  // Pi_ij, in units of pressure / rho^2
  double mu = 0.0;  // mu_ij (m/s, <= 0): feeds the signal speed of the time step
};

inline ViscousPair monaghan_viscosity(const ViscosityCoefficients& k, double vr, double r2,
                                      double h_ij, double c_ij, double rho_ij) {
  if (!(vr < 0.0)) return {};
  const double mu = h_ij * vr / (r2 + k.eta2 * h_ij * h_ij);
  return {(-k.alpha * c_ij * mu + k.beta * mu * mu) / rho_ij, mu};
}

// monaghan_viscosity without a branch, for the passes' lanes: Pi_ij selected on approach (0
// elsewhere), and mu_ij where Pi_ij acts (0 elsewhere). One division serves both mu_ij and
// 1 / rho_ij (r^2 + eta^2 h_ij^2 > 0 and rho_ij > 0), so Pi_ij differs from
// monaghan_viscosity's by a few ulp.
template <class T>
struct ViscousLanes {
  T pi;
  T mu;
};
// alpha and beta per lane: the pair's coefficients (constant, or the pair means of the
// Morris & Monaghan switch below). With T(k.alpha), T(k.beta) the same bits as the overload.
template <class T>
inline ViscousLanes<T> monaghan_viscosity_lanes(const T& alpha, const T& beta, double eta2,
                                                const T& vr, const T& r2, const T& h_ij,
                                                const T& c_ij, const T& rho_ij) {
  const T d1 = r2 + T(eta2) * h_ij * h_ij;
  const T inv = T(1.0) / (d1 * rho_ij);
  const T mu = h_ij * vr * rho_ij * inv;
  const T pi = simd::vselect(vr < T(0.0), (-alpha * c_ij * mu + beta * mu * mu) * d1 * inv, T(0.0));
  return {pi, simd::vselect(pi != T(0.0), mu, T(0.0))};
}
template <class T>
inline ViscousLanes<T> monaghan_viscosity_lanes(const ViscosityCoefficients& k, const T& vr,
                                                const T& r2, const T& h_ij, const T& c_ij,
                                                const T& rho_ij) {
  return monaghan_viscosity_lanes(T(k.alpha), T(k.beta), k.eta2, vr, r2, h_ij, c_ij, rho_ij);
}

// The viscosity switch of Morris & Monaghan (1997, J. Comput. Phys. 136, 41, Sec. 3): each
// particle carries its own alpha_i, which decays toward alpha_min away from compression and is
// raised where the flow converges,
//   d alpha_i/dt = -(alpha_i - alpha_min) / tau_i + S_i,   tau_i = h_i / (C c_i),
//   S_i = max(-div v_i, 0) (alpha_max - alpha_i),
// with the source limited by (alpha_max - alpha_i) as in Rosswog et al. (2000, MNRAS 317, 41)
// so that alpha_i stays in [alpha_min, alpha_max]; the pair uses the mean alpha_ij and
// beta_ij = 2 alpha_ij (Morris & Monaghan's choice). (Equation numbers of the two papers are not
// given here: neither paper is in the project's sources to check them against.)
struct SwitchCoefficients {
  double alpha_min = 0.1;
  double alpha_max = 1.0;
  double decay = 0.1;  // C of tau = h / (C c); Morris & Monaghan use 0.1-0.2
};

// One step of the switch: the equation above is linear in alpha, d alpha/dt = -k (alpha - a_eq)
// with k = 1/tau + S', S' = max(-div v, 0), a_eq = (alpha_min / tau + S' alpha_max) / k, and it
// is integrated exactly over dt with div v, c and h frozen at the step's values:
//   alpha^{n+1} = a_eq + (alpha^n - a_eq) exp(-k dt).
// So alpha never leaves [alpha_min, alpha_max] for any dt (an explicit Euler step would
// overshoot a_eq once k dt > 1, as in a strong shock where |div v| dt ~ 1), and without
// compression it decays exactly as exp(-t / tau).
inline double morris_monaghan_alpha(const SwitchCoefficients& k, double alpha, double div_v,
                                    double c, double h, double dt) {
  const double inv_tau = h > 0.0 ? k.decay * c / h : 0.0;
  const double src = div_v < 0.0 ? -div_v : 0.0;
  const double rate = inv_tau + src;
  if (!(rate > 0.0)) return alpha;
  const double a_eq = (k.alpha_min * inv_tau + src * k.alpha_max) / rate;
  return a_eq + (alpha - a_eq) * std::exp(-rate * dt);
}

// The viscous force and its heating (Monaghan 1992, Eqs. 4.1 and 4.4):
//   dv_i/dt += -m_j Pi_ij grad_i W_ij,   du_i/dt += 1/2 m_j Pi_ij v_ij . grad_i W_ij.
// Summed over i with m_i, the heating is exactly the kinetic energy the force removes, so the
// viscosity conserves total energy (it is not in the material model's deps : sigma work: the
// constitutive call gets zero viscosity coefficients).
template <class T>
inline void viscous_term(T (&acc)[3], T& heat, const T& m_j, const T& pi, const T (&vij)[3],
                         const T (&grad)[3]) {
  const T w = m_j * pi;
  acc[0] -= w * grad[0];
  acc[1] -= w * grad[1];
  acc[2] -= w * grad[2];
  heat += T(0.5) * w * (vij[0] * grad[0] + vij[1] * grad[1] + vij[2] * grad[2]);
}

// Time-centred viscous heating, the energy side of viscous_term over one kick. The force of the
// kick was made with the velocities v^{n-1/2}; over the kick it removes kinetic energy at the
// mean velocity (v^{n-1/2} + v^{n+1/2}) / 2, so the heat must be made with that mean to balance
// it to second order in dt (with v^{n-1/2} alone the total energy error of a viscous run is
// first order: 1.6e-3 and 7.9e-4 at CFL 0.3 and 0.15 in the colliding spheres). w is the pair
// weight the force pass stored, m_j Pi_ij F_ij (grad_i W_ij = F_ij x_ij at x^n), so that
//   du_i += 1/2 w (v_ij^{mean} . x_ij^n) dt_kick.
template <class T>
inline void viscous_heating_term(T& heat, const T& w, const T (&vij_mean)[3], const T (&xij)[3]) {
  heat += T(0.5) * w * (vij_mean[0] * xij[0] + vij_mean[1] * xij[1] + vij_mean[2] * xij[2]);
}

}  // namespace shatter::kernels::sph
