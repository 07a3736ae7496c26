#pragma once
// Gathers with up to eight particles per vector whose stencils are the same 27 nodes. Inside a
// block's list (SparseGrid, by (body, id)) the particles that share a stencil are mostly not
// neighbours (runs of 1.96 on lab-impact-coarse); the gathers visit them grouped by stencil
// base instead (6.9 per run, 86 % of the points in runs of eight; docs/performance.md,
// "Session 23: MPM transfers"), a stable counting sort of the list per chunk. For such a run a
// node's value is one broadcast for all lanes, where with each lane at its own stencil it was a
// gather (session 16: 2.9x slower than one particle at a time). Each lane does the operations of
// the one-particle gathers (g2p.hpp, velocity_gradient.hpp) in their order, and a gather's
// result depends on its particle alone: the same bits, whatever order the particles are visited
// in. P2G and the remap keep the list's order (their node sums depend on it).

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>

#include "mpm/stencil.hpp"

namespace shatter::kernels {

// Particle p's first stencil node's offsets in its owner block, packed as StencilCache::off:
// kernels::first_node per axis as the rows take it (uGIMP; the axisymmetric y axis at 0).
inline std::uint8_t stencil_base(const StencilCache& cache, std::uint32_t p) {
  unsigned base = 0;
  for (int d = 0; d < 3; ++d) {
    if (cache.axisymmetric && d == 1) continue;
    const double f = first_node(cache.x[d][p], cache.inv_h, GimpShape::kShift);
    base |= static_cast<unsigned>(static_cast<std::int64_t>(f) & 3) << (2 * d);
  }
  return static_cast<std::uint8_t>(base);
}

// body(rows, base, off, idx, count) for every particle of `particles` once, in runs of up to
// kStencilBatch particles with the same stencil base (stencil_base): the list is cut into chunks
// of kSharedChunk, each ordered by base by a stable counting sort (a function of the list alone).
// rows: the run's rows recomputed (StencilCache::kRecompute) as recomputed_rows lays them out,
// off[k] the offsets lane k's row came out at; `base` in every lane unless the two roundings of
// first_node differ, and a lane with off[k] != base must be gathered alone.
inline constexpr std::size_t kSharedChunk = 1024;

template <bool kGrad, class Body>
void for_each_shared_run(const StencilCache& cache, std::span<const std::uint32_t> particles,
                         Body&& body) {
  alignas(64) double rows[18 * kStencilBatch] = {};
  std::uint8_t off[kStencilBatch];
  std::uint32_t sorted[kSharedChunk];
  std::uint8_t bases[kSharedChunk], sorted_bases[kSharedChunk];
  for (std::size_t c0 = 0; c0 < particles.size(); c0 += kSharedChunk) {
    const std::size_t m = std::min(kSharedChunk, particles.size() - c0);
    std::uint32_t start[65] = {};
    for (std::size_t k = 0; k < m; ++k) {
      bases[k] = stencil_base(cache, particles[c0 + k]);
      ++start[bases[k] + 1];
    }
    for (int b = 0; b < 64; ++b) start[b + 1] += start[b];
    for (std::size_t k = 0; k < m; ++k) {
      const std::uint32_t at = start[bases[k]]++;
      sorted[at] = particles[c0 + k];
      sorted_bases[at] = bases[k];
    }
    for (std::size_t k0 = 0; k0 < m;) {
      const std::uint8_t base = sorted_bases[k0];
      std::size_t k1 = k0 + 1;
      while (k1 < m && k1 - k0 < kStencilBatch && sorted_bases[k1] == base) ++k1;
      const int count = static_cast<int>(k1 - k0);
      recomputed_rows<kGrad>(cache, sorted + k0, count, rows, off);
      body(static_cast<const double*>(rows), base, static_cast<const std::uint8_t*>(off),
           static_cast<const std::uint32_t*>(sorted + k0), count);
      k0 = k1;
    }
  }
}

// The window index of node (a, b, 0) of the stencil with packed offsets `base`.
inline int shared_row(unsigned base, int a, int b) {
  constexpr int e = WindowGeometry::kEdge;
  return ((static_cast<int>(base & 3U) + a) * e + static_cast<int>((base >> 2) & 3U) + b) * e +
         static_cast<int>((base >> 4) & 3U);
}

#if defined(SHATTER_AVX512_ROWS)
// G2P's sums for the eight lanes of `rows` (recomputed_rows' layout, uGIMP: W = 3) at the
// stencil `base`: s[f] lane k = sum over the nodes of N_k u_f, for the window's six fields of
// node values fp (acceleration, velocity) and, Filtered, the three of fv. Per node, N = (w_x
// w_y) w_z per lane and fma(N, u, sum), in the node order of g2p_gather: its bits.
template <bool Filtered>
[[gnu::always_inline]] inline void g2p_gather_shared(const double* rows, unsigned base,
                                                     const double* fp, const double* fv,
                                                     __m512d (&s)[6], __m512d (&t)[3]) {
  // Local accumulators, written out once: through the references GCC stored them every node.
  __m512d as[6], at[3];
  for (__m512d& v : as) v = _mm512_setzero_pd();
  for (__m512d& v : at) v = _mm512_setzero_pd();
  for (int a = 0; a < 3; ++a) {
    const __m512d wx = _mm512_loadu_pd(rows + a * kStencilBatch);
    for (int b = 0; b < 3; ++b) {
      const __m512d wab = _mm512_mul_pd(wx, _mm512_loadu_pd(rows + (3 + b) * kStencilBatch));
      const int row = shared_row(base, a, b);
      for (int c = 0; c < 3; ++c) {
        const __m512d N = _mm512_mul_pd(wab, _mm512_loadu_pd(rows + (6 + c) * kStencilBatch));
        const double* u = fp + 8 * (row + c);
        for (int f = 0; f < 6; ++f) as[f] = _mm512_fmadd_pd(N, _mm512_set1_pd(u[f]), as[f]);
        if constexpr (Filtered) {
          const double* q = fv + 4 * (row + c);
          for (int f = 0; f < 3; ++f) at[f] = _mm512_fmadd_pd(N, _mm512_set1_pd(q[f]), at[f]);
        }
      }
    }
  }
  for (int f = 0; f < 6; ++f) s[f] = as[f];
  for (int f = 0; f < 3; ++f) t[f] = at[f];
}

// The velocity gradient's sums for the eight lanes of `rows` (with derivatives) at the stencil
// `base`, v the window's velocity fields: L[r][q] lane k = sum over the nodes of G_q v_r, G =
// ((w'_x w_y) w_z, (w_x w'_y) w_z, (w_x w_y) w'_z) and, kInterpolated, L[r][3] with N = (w_x
// w_y) w_z; fma(G_q, v_r, L) per node in the node order of velocity_gradient_gather, whose
// lanes form the same products: its bits.
template <bool kInterpolated>
[[gnu::always_inline]] inline void velocity_gradient_shared(
    const double* rows, unsigned base, const double (&v)[3][WindowGeometry::kSize],
    __m512d (&out)[3][4]) {
  constexpr int Q = kInterpolated ? 4 : 3;
  __m512d L[3][4];  // local accumulators, written out once (as in g2p_gather_shared)
  for (auto& r : L) {
    for (__m512d& q : r) q = _mm512_setzero_pd();
  }
  const auto w = [&](int d, int a) { return _mm512_loadu_pd(rows + (3 * d + a) * kStencilBatch); };
  const auto dw = [&](int d, int a) {
    return _mm512_loadu_pd(rows + (9 + 3 * d + a) * kStencilBatch);
  };
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) {
      const __m512d ab[3] = {_mm512_mul_pd(dw(0, a), w(1, b)), _mm512_mul_pd(w(0, a), dw(1, b)),
                             _mm512_mul_pd(w(0, a), w(1, b))};
      const int row = shared_row(base, a, b);
      for (int c = 0; c < 3; ++c) {
        const __m512d g[4] = {_mm512_mul_pd(ab[0], w(2, c)), _mm512_mul_pd(ab[1], w(2, c)),
                              _mm512_mul_pd(ab[2], dw(2, c)), _mm512_mul_pd(ab[2], w(2, c))};
        for (int r = 0; r < 3; ++r) {
          const __m512d vr = _mm512_set1_pd(v[r][row + c]);
          for (int q = 0; q < Q; ++q) L[r][q] = _mm512_fmadd_pd(g[q], vr, L[r][q]);
        }
      }
    }
  }
  for (int r = 0; r < 3; ++r) {
    for (int q = 0; q < 4; ++q) out[r][q] = L[r][q];
  }
}
#endif

}  // namespace shatter::kernels
