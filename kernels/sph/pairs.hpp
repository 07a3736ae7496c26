#pragma once
// The two pair passes of the SPH step (DESIGN.md "The SPH step", steps 2 and 4) in the symmetric
// form: each pair within support evaluated once, from its lower particle i over the upper half
// of i's list (the entries j > i: a suffix of the ascending compacted list, upper_half), its
// terms added to i's sums in the lanes and to j's in the passes' columns (scatter). grad_j W_ji =
// -grad_i W_ij bitwise (terms.hpp), so the pair's two terms are the same values. Mirror particles
// (j >= real) take no share: their sums are never used (their state is copied from their
// sources), so a pair with an image is evaluated from the real side only, as in the gather
// passes. Each particle's sum thus collects its lower pairs' shares, in the order in which the
// caller runs the lower particles, and then its own upper pairs' lane sums: the caller must run
// the particles in an order that is a function of the lists alone (src/sph/tiles.cpp: tiles in a
// fixed colouring, no two tiles of a colour writing the same particle) for the bits to be
// independent of the thread count. The gather passes (gather.hpp) evaluate the same terms from
// both sides and serve as the tests' reference (round-off apart).
// Hot loops only: no I/O, no allocation.

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "sph/gather.hpp"

namespace shatter::kernels::sph {

// The first entry of i's ascending compacted list (nb, count) above i: the pairs j > i.
inline std::size_t upper_half(const std::uint32_t* nb, std::size_t count, std::size_t i) {
  return static_cast<std::size_t>(std::upper_bound(nb, nb + count, static_cast<std::uint32_t>(i)) -
                                  nb);
}

// Which lanes of a group take a share: the first rem, and only real particles.
template <std::size_t W>
inline unsigned real_lanes(const std::int64_t (&idx)[W], std::size_t rem, std::size_t real) {
  unsigned m = 0u;
  for (std::size_t l = 0; l < rem; ++l) {
    m |= static_cast<unsigned>(idx[l] < static_cast<std::int64_t>(real)) << l;
  }
  return m;
}

// Pass 2 in the symmetric form for particle i over the upper half of its pairs within support
// (nb, count: j > i; real: how many particles are real), with the same terms as
// forces_particle: Eq. 17 and Monaghan's viscosity as one pair vector (pair_force_term),
//   dv_i/dt += m_j P_ij,  dv_j/dt -= m_i P_ij,
// the heating 1/2 m_j Pi_ij v_ij . grad_i W_ij to each side with the other's mass (Monaghan
// 1992, Eq. 4.4; v_ji . grad_j W_ji is the same value) and |mu_ij| to both maxima. The sums go
// to rows: particle p's acceleration and heating rate at rows[8 p] .. rows[8 p + 3] (zero before
// the pass), the maxima to out.mu (zero before); the caller turns the rows into out.ax, ay, az,
// heat, with gravity, after the pass. The viscous weights Pi_ij F_ij (without a mass: each
// side of the next rates pass takes the other's) go to pair_w + w_offset as in forces_particle.
// Returns how many weights it wrote.
template <class T = double>
inline std::size_t forces_upper(const PairInputs& in, const ForceInputs& f, const std::uint32_t* nb,
                                std::size_t count, std::size_t i, std::size_t real, double* rows,
                                const ForceOutputs& out, std::size_t w_offset = 0,
                                std::size_t mask_offset = 0) {
  using L = Lanes<T>;
  constexpr std::size_t W = L::width;
  double* w = out.pair_w != nullptr ? out.pair_w + w_offset : nullptr;
  std::uint8_t* wmask = out.pair_mask + mask_offset;
  std::size_t written = 0;
  const double *X = in.x, *Y = in.y, *Z = in.z, *VX = in.vx, *VY = in.vy, *VZ = in.vz;
  const double *M = in.mass, *H = in.h, *R = in.rho, *C = f.soundspeed;
  const double* AS[6] = {f.a_stress[0], f.a_stress[1], f.a_stress[2],
                         f.a_stress[3], f.a_stress[4], f.a_stress[5]};
  const double* AL = f.alpha;
  double* MU = out.mu;
  const T xi(X[i]), yi(Y[i]), zi(Z[i]), hi(H[i]), rhoi(R[i]), ci(C[i]), mi(M[i]);
  const T alphai(AL != nullptr ? AL[i] : 0.0);
  const T vi[3] = {T(VX[i]), T(VY[i]), T(VZ[i])};
  T A_i[6];
  for (int c = 0; c < 6; ++c) A_i[c] = T(AS[c][i]);
  T acc[3] = {T(0.0), T(0.0), T(0.0)};
  T heat(0.0), mu_max(0.0);
  alignas(64) std::int64_t idx[W];
  for (std::size_t k = 0; k < count; k += W) {
    bool run = false;
    const std::size_t rem = group_indices<W>(nb, count, k, i, idx, run);
    const T dx[3] = {xi - L::gather(X, idx, run), yi - L::gather(Y, idx, run),
                     zi - L::gather(Z, idx, run)};
    const T r2 = dx[0] * dx[0] + dx[1] * dx[1] + dx[2] * dx[2];
    const T h_ij = T(0.5) * (hi + L::gather(H, idx, run));
    const T F = cubic_f_lanes(simd::vsqrt(r2), h_ij);
    const T grad[3] = {F * dx[0], F * dx[1], F * dx[2]};
    const T mj = L::gather(M, idx, run);
    const T rhoj = L::gather(R, idx, run);
    T A_j[6];
    for (int c = 0; c < 6; ++c) A_j[c] = L::gather(AS[c], idx, run);
    const T vij[3] = {vi[0] - L::gather(VX, idx, run), vi[1] - L::gather(VY, idx, run),
                      vi[2] - L::gather(VZ, idx, run)};
    const T vr = vij[0] * dx[0] + vij[1] * dx[1] + vij[2] * dx[2];
    const T c_ij = T(0.5) * (ci + L::gather(C, idx, run));
    const T rho_ij = T(0.5) * (rhoi + rhoj);
    ViscousLanes<T> q;
    if (AL == nullptr) {
      q = monaghan_viscosity_lanes(f.viscosity, vr, r2, h_ij, c_ij, rho_ij);
    } else {
      const T alpha_ij = T(0.5) * (alphai + L::gather(AL, idx, run));
      q = monaghan_viscosity_lanes(alpha_ij, T(2.0) * alpha_ij, f.viscosity.eta2, vr, r2, h_ij,
                                   c_ij, rho_ij);
    }
    T P[3];
    pair_force_term(P, f.normalized ? T(1.0) / (rhoi * rhoj) : T(1.0), A_i, A_j, q.pi, grad);
    const T hq = pair_heating_term(q.pi, vij, grad);
    const T mu = -q.mu;
    for (int d = 0; d < 3; ++d) acc[d] += mj * P[d];
    heat += mj * hq;
    mu_max = simd::vmax(mu_max, mu);
    const unsigned share = real_lanes<W>(idx, rem, real);
    const T j_side[4] = {-(mi * P[0]), -(mi * P[1]), -(mi * P[2]), mi * hq};
    L::add_rows(rows, 8, idx, j_side, share);
    L::max_to(MU, idx, mu, share);
    if (w != nullptr) {
      const unsigned m = L::store_nonzero(w + written, q.pi * F, rem);
      wmask[k / W] = static_cast<std::uint8_t>(m);
      written += static_cast<std::size_t>(__builtin_popcount(m));
    }
  }
  double* own = rows + 8 * i;
  own[0] += L::sum(acc[0]);
  own[1] += L::sum(acc[1]);
  own[2] += L::sum(acc[2]);
  own[3] += L::sum(heat);
  MU[i] = std::max(MU[i], L::max(mu_max));
  return written;
}

// What rates_upper adds to, per particle p: the velocity gradient's sums (Lsum of write_rates,
// row-major a, b) L_00 .. L_21 at rows8[8 p] .. rows8[8 p + 7], L_22 and the kick's viscous heat
// before the factor dt_kick at rows2[2 p], rows2[2 p + 1].
struct RateSums {
  double* rows8 = nullptr;
  double* rows2 = nullptr;
};

// Pass 1 in the symmetric form for particle i over the upper half of its pairs within support
// (nb, count; real as in forces_upper), with rates_particle's terms (Eq. 18 at the midpoint
// configuration, its trace Eq. 16; the kick's viscous heat from the weights forces_upper
// stored): rho_i L_i^{ab} += m_j dv^a grad_i^b and rho_j L_j^{ab} += m_i dv^a grad_i^b (dv =
// v_j - v_i; both signs flip for j), with the normalized continuity's weights m_j rho_i / rho_j
// and m_i rho_j / rho_i. The sums go to `sums` (zero before the pass); the caller turns them into
// the rates (write_rates) after the pass. rho_n: rho^n of every particle (out.rho_n of the gather
// pass), or nullptr for BA95's weights. Returns how many weights it read.
template <class T = double>
inline std::size_t rates_upper(const PairInputs& in, const std::uint32_t* nb, std::size_t count,
                               std::size_t i, std::size_t real, double dt, const double* rho_n,
                               const RateSums& sums, const KickHeating& kick = {},
                               std::size_t w_offset = 0, std::size_t mask_offset = 0) {
  using L = Lanes<T>;
  constexpr std::size_t W = L::width;
  const double *X = in.x, *Y = in.y, *Z = in.z, *VX = in.vx, *VY = in.vy, *VZ = in.vz;
  const double *M = in.mass, *H = in.h, *RN = rho_n;
  const T xi(X[i]), yi(Y[i]), zi(Z[i]), hi(H[i]), mi(M[i]);
  const T rhoi_n(RN != nullptr ? RN[i] : 1.0);
  const T vi[3] = {T(VX[i]), T(VY[i]), T(VZ[i])};
  const T half_dt(0.5 * dt);
  T Ls[3][3];
  for (auto& row : Ls) {
    for (T& v : row) v = T(0.0);
  }
  T heat(0.0);
  const double* w = kick.pair_w != nullptr ? kick.pair_w + w_offset : nullptr;
  const std::uint8_t* wmask = kick.pair_mask + mask_offset;
  std::size_t read = 0;
  const T half_kick(0.5 * kick.dt_kick);
  const T axi(w != nullptr ? kick.ax[i] : 0.0), ayi(w != nullptr ? kick.ay[i] : 0.0),
      azi(w != nullptr ? kick.az[i] : 0.0);
  alignas(64) std::int64_t idx[W];
  for (std::size_t k = 0; k < count; k += W) {
    bool run = false;
    const std::size_t rem = group_indices<W>(nb, count, k, i, idx, run);
    const unsigned share = real_lanes<W>(idx, rem, real);
    const T xj = L::gather(X, idx, run), yj = L::gather(Y, idx, run), zj = L::gather(Z, idx, run);
    const T dv[3] = {L::gather(VX, idx, run) - vi[0], L::gather(VY, idx, run) - vi[1],
                     L::gather(VZ, idx, run) - vi[2]};
    const T mj = L::gather(M, idx, run);
    T hq(0.0);
    if (w != nullptr) {
      // v_ij at the middle of the kick (rates_particle; terms.hpp, viscous_heating_term), the
      // weight Pi_ij F_ij of the pair, +0 off approach.
      const T vm[3] = {-dv[0] - half_kick * (axi - L::gather(kick.ax, idx, run)),
                       -dv[1] - half_kick * (ayi - L::gather(kick.ay, idx, run)),
                       -dv[2] - half_kick * (azi - L::gather(kick.az, idx, run))};
      const T xij[3] = {xi - xj, yi - yj, zi - zj};
      const unsigned m = wmask[k / W];
      viscous_heating_term(hq, L::load_nonzero(w + read, m), vm, xij);
      read += static_cast<std::size_t>(__builtin_popcount(m));
      heat += mj * hq;
    }
    // The midpoint separation of rates_particle.
    const T dx[3] = {xi - xj - half_dt * dv[0], yi - yj - half_dt * dv[1],
                     zi - zj - half_dt * dv[2]};
    const T r = simd::vsqrt(dx[0] * dx[0] + dx[1] * dx[1] + dx[2] * dx[2]);
    const T F = cubic_f_lanes(r, T(0.5) * (hi + L::gather(H, idx, run)));
    const T grad[3] = {F * dx[0], F * dx[1], F * dx[2]};
    T wi = mj, wj = mi;
    if (RN != nullptr) {
      // The normalized weights (rates_particle; Randles & Libersky 1996).
      const T rhoj_n = L::gather(RN, idx, run);
      wi = mj * (rhoi_n / rhoj_n);
      wj = mi * (rhoj_n / rhoi_n);
    }
    velocity_gradient_term(Ls, wi, dv, grad);
    T Lj[3][3];
    for (auto& row : Lj) {
      for (T& v : row) v = T(0.0);
    }
    velocity_gradient_term(Lj, wj, dv, grad);
    const T j8[8] = {Lj[0][0], Lj[0][1], Lj[0][2], Lj[1][0],
                     Lj[1][1], Lj[1][2], Lj[2][0], Lj[2][1]};
    const T j2[2] = {Lj[2][2], mi * hq};
    L::add_rows(sums.rows8, 8, idx, j8, share);
    L::add_rows(sums.rows2, 2, idx, j2, share);
  }
  double* own8 = sums.rows8 + 8 * i;
  double* own2 = sums.rows2 + 2 * i;
  for (int c = 0; c < 8; ++c) own8[c] += L::sum(Ls[c / 3][c % 3]);
  own2[0] += L::sum(Ls[2][2]);
  own2[1] += L::sum(heat);
  return read;
}

}  // namespace shatter::kernels::sph
