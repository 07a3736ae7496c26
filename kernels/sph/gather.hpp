#pragma once
// The two gather passes of the SPH step (DESIGN.md "The SPH step", steps 2 and 4): each
// particle sums its own neighbours, in the fixed order of its neighbour list, and writes only
// its own outputs. No scatter, so the result has the same bits on any number of threads.
// Hot loops only: no I/O, no allocation.
//
// Both passes are templates over T: double (the scalar reference, one neighbour at a time) or
// simd::Batch (W neighbours at a time, one per SIMD lane: W = 8 doubles with AVX-512, 4 with
// AVX2). The lanes take the list in consecutive groups of W, gather the neighbours' columns, and
// keep one partial sum per lane, added up at the end; the pair terms are the same expressions
// but branch-free (cubic_f_lanes, the viscosity selected on approach). So the batch path sums
// the same terms in another order than the scalar one (round-off, tested against it) and its
// bits depend on W, but not on the thread count, and not on a Verlet skin: the passes run over
// the compacted list of pairs within support (compact_within_support), which is the same with
// and without a skin. The last group is padded with i itself, whose terms are exactly zero
// (x_ii = 0 and v_ii = 0 make every pair term 0, and the inner kernel branch is finite).

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#if defined(__AVX512F__)
#include <immintrin.h>
#endif

#include "constitutive/simd.hpp"
#include "sph/cubic_spline.hpp"
#include "sph/terms.hpp"

namespace shatter::kernels::sph {

// The lanes of T: its width, gathers of neighbour columns, sums and maxima across lanes.
template <class T>
struct Lanes {
  static constexpr std::size_t width = 1;
  using Index = std::int64_t;
  static double gather(const double* col, const Index* idx, bool /*run*/) { return col[idx[0]]; }
  static double load(const double* p) { return *p; }
  static void store(double* p, double v) { *p = v; }
  // The non-zero lanes of v among the first rem, packed to p[0 ..) in lane order (the viscous
  // weights, stored_weights below); returns which lanes (bit l: lane l) were written.
  static unsigned store_nonzero(double* p, double v, std::size_t /*rem*/) {
    if (v == 0.0) return 0u;
    *p = v;
    return 1u;
  }
  // The inverse: the lanes of `mask` from p[0 ..), +0 in the others.
  static double load_nonzero(const double* p, unsigned mask) { return mask != 0u ? *p : 0.0; }
  static double sum(double v) { return v; }
  static double max(double v) { return v; }
};
template <class A>
struct Lanes<xsimd::batch<double, A>> {
  using B = xsimd::batch<double, A>;
  static constexpr std::size_t width = B::size;
  using Index = std::int64_t;
  static_assert(width <= 8, "a group's weight mask is one byte");
  // Element by element into an aligned buffer, then one load. Not the hardware gather: on the
  // development machine (AMD EPYC, AVX-512) vgatherqpd made the whole step 1.3x slower
  // (docs/performance.md, SPH section), and xsimd 8.1's batch::gather does not even reach it
  // for doubles (it calls an out-of-line generic gather, a quarter of the step under perf).
  static B gather(const double* col, const Index* idx, bool run) {
    if (run) return B::load_unaligned(col + idx[0]);
    alignas(64) double v[width];
    for (std::size_t l = 0; l < width; ++l) v[l] = col[idx[l]];
    return B::load_aligned(v);
  }
  static B load(const double* p) { return B::load_aligned(p); }
  static void store(double* p, const B& v) { v.store_aligned(p); }
  // As Lanes<double>: with AVX-512, the lanes packed in a register (vcompresspd, whose store
  // form is slow on Zen 4) and stored as one masked store, and read back as one masked load
  // spread out in the register (vexpandpd).
  static unsigned store_nonzero(double* p, const B& v, std::size_t rem) {
#if defined(__AVX512F__)
    if constexpr (width == 8) {
      const auto mask = static_cast<__mmask8>(
          _mm512_cmp_pd_mask(v, _mm512_setzero_pd(), _CMP_NEQ_UQ) & ((1u << rem) - 1u));
      const auto packed = static_cast<__mmask8>((1u << __builtin_popcount(mask)) - 1u);
      _mm512_mask_storeu_pd(p, packed, _mm512_maskz_compress_pd(mask, v));
      return mask;
    }
#endif
    alignas(64) double a[width];
    v.store_aligned(a);
    unsigned mask = 0u, m = 0u;
    for (std::size_t l = 0; l < rem; ++l) {
      if (a[l] != 0.0) {
        p[m++] = a[l];
        mask |= 1u << l;
      }
    }
    return mask;
  }
  static B load_nonzero(const double* p, unsigned mask) {
#if defined(__AVX512F__)
    if constexpr (width == 8) {
      const auto packed = static_cast<__mmask8>((1u << __builtin_popcount(mask)) - 1u);
      return B(
          _mm512_maskz_expand_pd(static_cast<__mmask8>(mask), _mm512_maskz_loadu_pd(packed, p)));
    }
#endif
    alignas(64) double a[width] = {};
    unsigned m = 0u;
    for (std::size_t l = 0; l < width; ++l) {
      if ((mask >> l) & 1u) a[l] = p[m++];
    }
    return B::load_aligned(a);
  }
  static double sum(const B& v) {
    return xsimd::hadd(v);
  }
  static double max(const B& v) {
    alignas(64) double a[width];
    v.store_aligned(a);
    double m = a[0];
    for (std::size_t l = 1; l < width; ++l) m = std::max(m, a[l]);
    return m;
  }
};

// Indices of the next group of at most W list entries, padded with i; `run` tells whether they
// are W consecutive indices, which the gathers then read as one load per column. (Particles
// re-ordered by cell make such runs common: in the benchmark cube they made the step 1.2x
// faster. The values are the same either way, so are the bits.)
template <std::size_t W>
inline std::size_t group_indices(const std::uint32_t* nb, std::size_t count, std::size_t k,
                                 std::size_t i, std::int64_t (&idx)[W], bool& run) {
  const std::size_t rem = std::min(W, count - k);
  bool consecutive = rem == W;
  for (std::size_t l = 0; l < W; ++l) {
    idx[l] = static_cast<std::int64_t>(l < rem ? nb[k + l] : i);
    consecutive &= idx[l] == idx[0] + static_cast<std::int64_t>(l);
  }
  run = consecutive;
  return rem;
}

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
};

// |x_i - x_j|^2 as the neighbour search (src/sph/neighbours.cpp) and compact_within_support
// both compute it, so that they decide every pair alike. With FMA, the two fused multiply-adds
// that GCC 12 contracted dx dx + dy dy + dz dz into in both places at -O2 and above (read from the
// object code, session 19), spelled out so that neither the optimisation level nor the SIMD
// path below changes them; without FMA, the plain sum.
inline double distance2(double dx, double dy, double dz) {
#if defined(__FMA__)
  return std::fma(dz, dz, std::fma(dx, dx, dy * dy));
#else
  return dx * dx + dy * dy + dz * dz;
#endif
}

// list[0 .. sorted) ascending, list[sorted .. end) in any order: the whole ascending, by insertion
// from `sorted` (few entries there: those that came within support since the last call).
inline void sort_tail(std::uint32_t* list, std::size_t sorted, std::size_t end) {
  for (std::size_t t = std::max<std::size_t>(1, sorted); t < end; ++t) {
    const std::uint32_t j = list[t];
    std::size_t u = t;
    for (; u > 0 && list[u - 1] > j; --u) list[u] = list[u - 1];
    list[u] = j;
  }
}

// i's Verlet list (list, count) rearranged in place: its entries within support at the current
// positions, |x_i - x_j| < h_i + h_j by the neighbour search's own expression
// (src/sph/neighbours.cpp), first and in ascending index order (the compacted list: exactly the
// list a search without the skin makes), then the others (the skin's entries, in an order of no
// meaning). Returns how many are within support. On entry the first `sorted` entries must be in
// ascending order (a list as a build or NeighbourSearch::permute leaves it: sorted = count; or
// as this function left it: sorted = its last return); the rest may be in any order. `rest` is
// scratch with room for count + 8 entries. The compacted list then needs no storage of its own
// (it had 4 B per list entry, ~300 B per point in the benchmark's cube, session 20).
//
// While every entry keeps the status it had (within support iff before `sorted`), nothing is
// written: the list is already in its final order (in a slow flow most lists end so). From the
// first entry that changed, the kept entries are moved to the front (m <= k) and the others to
// `rest`, which is copied back behind them at the end; kept entries from the unsorted part
// (pairs that came within support since the last call: few) are then sorted in by insertion.
//
// The distance test is distance2's, in the lanes too, so that both paths decide every pair alike
// and as before. With AVX-512 (VL) the list is taken 8 entries at a time: the neighbours' x, y,
// z, h gathered into lanes, the test as a mask, the indices compressed in a register (vpcompressd;
// its store form is slow on Zen 4) and stored as 8 lanes at the current ends (the lanes past the
// kept ones stay inside the 8 entries just read).
inline std::size_t partition_within_support(const PairInputs& in, std::uint32_t* list,
                                            std::size_t count, std::size_t sorted, std::size_t i,
                                            std::uint32_t* rest) {
  const double xi = in.x[i], yi = in.y[i], zi = in.z[i], hi = in.h[i];
  // m: entries kept so far, o: others in `rest`, k: the next entry; m_sorted: how many of the
  // kept come from the sorted part (set when k reaches it). While `same`, list[0, m) are the kept
  // entries and list[m, k) the others, in place.
  std::size_t m = 0, o = 0, k = 0, m_sorted = count + 1;
  bool same = true;
  const auto diverge = [&] {
    std::copy(list + m, list + k, rest);
    o = k - m;
    same = false;
  };
#if defined(__AVX512F__) && defined(__AVX512VL__) && defined(__FMA__)
  const __m512d XI = _mm512_set1_pd(xi), YI = _mm512_set1_pd(yi), ZI = _mm512_set1_pd(zi),
                HI = _mm512_set1_pd(hi);
  const auto lanes = [](const double* col, const std::uint32_t* j) {
    return _mm512_setr_pd(col[j[0]], col[j[1]], col[j[2]], col[j[3]], col[j[4]], col[j[5]],
                          col[j[6]], col[j[7]]);
  };
  for (; k + 8 <= count; k += 8) {
    const std::uint32_t* j = list + k;
    const __m512d dx = _mm512_sub_pd(XI, lanes(in.x, j));
    const __m512d dy = _mm512_sub_pd(YI, lanes(in.y, j));
    const __m512d dz = _mm512_sub_pd(ZI, lanes(in.z, j));
    const __m512d reach = _mm512_add_pd(HI, lanes(in.h, j));
    const __m512d r2 = _mm512_fmadd_pd(dz, dz, _mm512_fmadd_pd(dx, dx, _mm512_mul_pd(dy, dy)));
    const __mmask8 within = _mm512_cmp_pd_mask(r2, _mm512_mul_pd(reach, reach), _CMP_LT_OQ);
    // The lanes before `sorted`: those within support at the last call.
    const auto was = static_cast<__mmask8>(
        sorted >= k + 8 ? 0xffu : (sorted > k ? (1u << (sorted - k)) - 1u : 0u));
    if (sorted >= k && sorted < k + 8) {
      m_sorted = m + static_cast<std::size_t>(__builtin_popcount(within & was));
    }
    const auto kept = static_cast<std::size_t>(__builtin_popcount(within));
    if (same) {
      if (within == was) {
        m += kept;
        continue;
      }
      diverge();
    }
    const __m256i idx = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(j));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(list + m),
                        _mm256_maskz_compress_epi32(within, idx));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(rest + o),
                        _mm256_maskz_compress_epi32(static_cast<__mmask8>(~within), idx));
    m += kept;
    o += 8 - kept;
  }
#endif
  for (; k < count; ++k) {
    if (k == sorted) m_sorted = m;
    const std::uint32_t j = list[k];
    const double dx = xi - in.x[j], dy = yi - in.y[j], dz = zi - in.z[j];
    const double reach = hi + in.h[j];
    const std::size_t kept = distance2(dx, dy, dz) < reach * reach ? 1 : 0;
    if (same) {
      if (kept == (k < sorted ? 1u : 0u)) {
        m += kept;
        continue;
      }
      diverge();
    }
    list[m] = j;
    rest[o] = j;
    m += kept;
    o += 1 - kept;
  }
  if (same) return m;
  sort_tail(list, std::min(m_sorted, m), m);
  std::copy(rest, rest + o, list + m);
  return m;
}

// Pass 1 outputs: the increments MaterialModel::update expects (App. A.2 step 7 of the MPM
// paper, same columns as MPM), and rho^{n+1}. L below is the sum of Eq. 18 before the division
// by rho (S^{ab} = sum_j m_j (v_j^a - v_i^a) dW_ij/dx_i^b).
struct RateOutputs {
  double* deps[6] = {};   // xx, yy, zz, xy, yz, xz: eps_dot dt (Eq. 18)
  double* dspin[3] = {};  // xy, yz, xz: omega dt, omega = (L - L^T) / 2
  double* rho = nullptr;  // in: rho^n, out: rho^{n+1}
  // The normalized continuity (SphConfig::Continuity::normalized): rho^n of every particle
  // (real and mirror), a copy, since `rho` is overwritten during the pass. nullptr = BA95's
  // Eq. 16 as printed.
  const double* rho_n = nullptr;
};

// The kick's viscous heating, made in the same pass (viscous_heating_term). Optional: with
// pair_w == nullptr no heat is computed.
struct KickHeating {
  const double* pair_w = nullptr;  // the non-zero weights, from the force pass (ForceOutputs)
  const std::uint8_t* pair_mask = nullptr;  // which entries they are (ForceOutputs)
  const double* ax = nullptr;               // a^n of the kick
  const double* ay = nullptr;
  const double* az = nullptr;
  double dt_kick = 0.0;
  double* heat = nullptr;  // out: specific heat added over the kick (J/kg)
};

// The end of pass 1 for particle i from the summed velocity gradient (Lsum: the sum of Eq. 18
// before the division by rho): rho^{n+1} and the strain and spin increments.
inline void write_rates(const double (&Lsum)[3][3], double rho_i, double dt, const RateOutputs& out,
                        std::size_t i) {
  // Eq. 16, forward in time: rho^{n+1} = rho^n - dt sum_j m_j (v_j - v_i) . grad_i W_ij.
  const double rho_new = rho_i - dt * (Lsum[0][0] + Lsum[1][1] + Lsum[2][2]);
  // Eq. 18 divides the sum by rho_i; with rho^{n+1} here, 1 + tr deps = rho^n / rho^{n+1}
  // exactly, which is the density relation MaterialModel::update assumes (it recovers rho^n as
  // rho (1 + tr deps) for its energy update dE = deps : sigma / rho^n). The pair then matches
  // the momentum equation's sigma / rho^2 at both ends of the step, which makes the total energy
  // error second order in dt (with rho^n here it was first order, measured).
  const double kf = dt / rho_new;
  out.deps[0][i] = kf * Lsum[0][0];
  out.deps[1][i] = kf * Lsum[1][1];
  out.deps[2][i] = kf * Lsum[2][2];
  out.deps[3][i] = 0.5 * kf * (Lsum[0][1] + Lsum[1][0]);
  out.deps[4][i] = 0.5 * kf * (Lsum[1][2] + Lsum[2][1]);
  out.deps[5][i] = 0.5 * kf * (Lsum[0][2] + Lsum[2][0]);
  out.dspin[0][i] = 0.5 * kf * (Lsum[0][1] - Lsum[1][0]);
  out.dspin[1][i] = 0.5 * kf * (Lsum[1][2] - Lsum[2][1]);
  out.dspin[2][i] = 0.5 * kf * (Lsum[0][2] - Lsum[2][0]);
  out.rho[i] = rho_new;
}

// Pass 1 for particle i (positions x^n, velocities v^{n+1/2}) over its pairs within support
// (nb, count; its viscous weights from pair_w + w_offset and pair_mask + mask_offset, as
// forces_particle stored them): velocity gradient from Eq. 18 (its trace is Eq. 16) at the
// step's midpoint configuration, turned into the strain and spin increments over dt and the
// density rho^{n+1}. Returns how many weights it read.
template <class T = double>
inline std::size_t rates_particle(const PairInputs& in, const std::uint32_t* nb, std::size_t count,
                                  std::size_t i, double dt, const RateOutputs& out,
                                  const KickHeating& kick = {}, std::size_t w_offset = 0,
                                  std::size_t mask_offset = 0) {
  using L = Lanes<T>;
  constexpr std::size_t W = L::width;
  // Local copies of the column pointers: the stores below cannot alias them in the compiler's
  // eyes, so they stay in registers.
  const double *X = in.x, *Y = in.y, *Z = in.z, *VX = in.vx, *VY = in.vy, *VZ = in.vz;
  const double *M = in.mass, *H = in.h, *RN = out.rho_n;
  const T xi(X[i]), yi(Y[i]), zi(Z[i]), hi(H[i]);
  const T rhoi_n(RN != nullptr ? RN[i] : 0.0);
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
    group_indices<W>(nb, count, k, i, idx, run);
    const T xj = L::gather(X, idx, run), yj = L::gather(Y, idx, run), zj = L::gather(Z, idx, run);
    const T dv[3] = {L::gather(VX, idx, run) - vi[0], L::gather(VY, idx, run) - vi[1],
                     L::gather(VZ, idx, run) - vi[2]};
    if (w != nullptr) {
      // v_ij at the middle of the kick: v^{n+1/2} - (a_i - a_j) dt_kick / 2 (terms.hpp,
      // viscous_heating_term). Pairs without viscosity have w = 0 and add exactly 0.
      const T vm[3] = {-dv[0] - half_kick * (axi - L::gather(kick.ax, idx, run)),
                       -dv[1] - half_kick * (ayi - L::gather(kick.ay, idx, run)),
                       -dv[2] - half_kick * (azi - L::gather(kick.az, idx, run))};
      const T xij[3] = {xi - xj, yi - yj, zi - zj};
      // The weights of the group's non-zero lanes; a lane without one takes +0, which adds
      // exactly nothing (a lane's sum starts at +0 and is never -0), as the -0 or +0 stored
      // before did (Pi_ij = 0 off approach).
      const unsigned m = wmask[k / W];
      viscous_heating_term(heat, L::load_nonzero(w + read, m), vm, xij);
      read += static_cast<std::size_t>(__builtin_popcount(m));
    }
    // Separation at the midpoint x^{n+1/2} = x^n + v^{n+1/2} dt / 2 of the step the increments
    // cover (midpoint rule: the stress work then matches the leapfrog's kinetic energy change
    // to second order in dt; at x^n it was first order, measured). Pairs that come within
    // reach during the half step are missed, at the kernel's edge where W and dW/dr vanish.
    const T dx[3] = {xi - xj - half_dt * dv[0], yi - yj - half_dt * dv[1],
                     zi - zj - half_dt * dv[2]};
    const T r = simd::vsqrt(dx[0] * dx[0] + dx[1] * dx[1] + dx[2] * dx[2]);
    const T F = cubic_f_lanes(r, T(0.5) * (hi + L::gather(H, idx, run)));
    const T grad[3] = {F * dx[0], F * dx[1], F * dx[2]};
    if (RN == nullptr) {
      velocity_gradient_term(Ls, L::gather(M, idx, run), dv, grad);
    } else {
      // Normalized form: m_j -> rho_i m_j / rho_j, so that Ls / rho_i (the velocity gradient
      // of Eq. 18, whose trace drives Eq. 16) weighs each neighbour by its own volume
      // m_j / rho_j (Randles & Libersky 1996, Comput. Methods Appl. Mech. Engrg. 139, 375: the
      // continuity equation drho_i/dt = rho_i sum_j (m_j / rho_j) (v_i - v_j) . grad_i W_ij and
      // the velocity gradient with the same weights). With BA95's m_j / rho_i weights a
      // particle whose density falls below its neighbours' sees their mass in its divergence:
      // its relative rate is (rho_j / rho_i) div v, which grows as rho_i falls, and an
      // expanding particle among denser ones reaches rho = 0 in finite time.
      velocity_gradient_term(Ls, L::gather(M, idx, run) * (rhoi_n / L::gather(RN, idx, run)), dv,
                             grad);
    }
  }
  double Lsum[3][3];
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) Lsum[a][b] = L::sum(Ls[a][b]);
  }
  write_rates(Lsum, in.rho[i], dt, out, i);
  if (kick.heat != nullptr) kick.heat[i] = L::sum(heat) * kick.dt_kick;
  return read;
}

// Pass 2 inputs besides PairInputs.
struct ForceInputs {
  const double* a_stress[6] = {};  // sigma / rho^2 per particle (Voigt), precomputed; with
                                   // `normalized`, sigma itself
  // The momentum equation that pairs with the normalized continuity (SphConfig::Continuity):
  //   dv_i/dt = sum_j m_j (sigma_i + sigma_j) / (rho_i rho_j) . grad_i W_ij
  // (the (P_i + P_j) / (rho_i rho_j) form of Monaghan 1992, Sec. 3, with the full stress). Its
  // work, summed over the pairs, is sum_i (m_i / rho_i) sigma_i : L_i with L_i the velocity
  // gradient weighted by m_j / rho_j, which is exactly the energy the material update takes
  // from deps (so total energy is conserved as with BA95's pair; with Eq. 17's
  // sigma / rho^2 form beside the normalized gradient it is not: +7 % in 6 us, measured).
  bool normalized = false;
  const double* soundspeed = nullptr;
  ViscosityCoefficients viscosity;
  // The Morris & Monaghan switch (terms.hpp): alpha per particle (real and mirror); the pair
  // takes alpha_ij = (alpha_i + alpha_j) / 2 and beta_ij = 2 alpha_ij. nullptr = viscosity's
  // constant alpha and beta.
  const double* alpha = nullptr;
  double gravity[3] = {0.0, 0.0, 0.0};
};

struct ForceOutputs {
  double* ax = nullptr;
  double* ay = nullptr;
  double* az = nullptr;
  double* heat = nullptr;  // viscous heating rate at the force's velocities (J/kg/s)
  double* mu = nullptr;    // max_j |mu_ij| (m/s), for the time step
  // The viscous weights m_j Pi_ij F_ij for viscous_heating_term, only the non-zero ones (the
  // pairs on approach: about half in the benchmark's cube), packed in list order; and per group
  // of W list entries a byte whose bit l tells whether entry k + l has one.
  double* pair_w = nullptr;
  std::uint8_t* pair_mask = nullptr;
};

// Pass 2 for particle i over its pairs within support (nb, count; its viscous weights written
// to pair_w + w_offset and its groups' masks to pair_mask + mask_offset): Eq. 17 with the full
// stress, Monaghan's viscosity and its heating (terms.hpp: stress_force_term,
// monaghan_viscosity_lanes, viscous_term), with constant coefficients or the switch's
// per-particle alpha. Returns how many weights it wrote.
template <class T = double>
inline std::size_t forces_particle(const PairInputs& in, const ForceInputs& f,
                                   const std::uint32_t* nb, std::size_t count, std::size_t i,
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
  const T xi(X[i]), yi(Y[i]), zi(Z[i]), hi(H[i]), rhoi(R[i]), ci(C[i]);
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
    T A_j[6];
    for (int c = 0; c < 6; ++c) A_j[c] = L::gather(AS[c], idx, run);
    if (f.normalized) {
      stress_force_term(acc, mj / (rhoi * L::gather(R, idx, run)), A_i, A_j, grad);
    } else {
      stress_force_term(acc, mj, A_i, A_j, grad);
    }
    const T vij[3] = {vi[0] - L::gather(VX, idx, run), vi[1] - L::gather(VY, idx, run),
                      vi[2] - L::gather(VZ, idx, run)};
    const T vr = vij[0] * dx[0] + vij[1] * dx[1] + vij[2] * dx[2];
    const T c_ij = T(0.5) * (ci + L::gather(C, idx, run));
    const T rho_ij = T(0.5) * (rhoi + L::gather(R, idx, run));
    ViscousLanes<T> q;
    if (AL == nullptr) {
      q = monaghan_viscosity_lanes(f.viscosity, vr, r2, h_ij, c_ij, rho_ij);
    } else {
      const T alpha_ij = T(0.5) * (alphai + L::gather(AL, idx, run));
      q = monaghan_viscosity_lanes(alpha_ij, T(2.0) * alpha_ij, f.viscosity.eta2, vr, r2, h_ij,
                                   c_ij, rho_ij);
    }
    viscous_term(acc, heat, mj, q.pi, vij, grad);
    mu_max = simd::vmax(mu_max, -q.mu);
    const T wv = mj * q.pi;
    if (w != nullptr) {
      const unsigned m = L::store_nonzero(w + written, wv * F, rem);
      wmask[k / W] = static_cast<std::uint8_t>(m);
      written += static_cast<std::size_t>(__builtin_popcount(m));
    }
  }
  out.ax[i] = L::sum(acc[0]) + f.gravity[0];
  out.ay[i] = L::sum(acc[1]) + f.gravity[1];
  out.az[i] = L::sum(acc[2]) + f.gravity[2];
  out.heat[i] = L::sum(heat);
  out.mu[i] = L::max(mu_max);
  return written;
}

}  // namespace shatter::kernels::sph
