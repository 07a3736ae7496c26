#pragma once
// The nodes a particle talks to and their weights: per-axis shape values and the position of the
// stencil inside the particle's owner block (see SparseGrid).

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <type_traits>

#if defined(__AVX512F__) && defined(__AVX512VL__) && defined(__AVX512DQ__)
#define SHATTER_AVX512_ROWS 1
#include <immintrin.h>
#endif

#include "mpm/shape.hpp"
#include "shatter/grid/sparse_grid.hpp"

namespace shatter::kernels {

// The stencils of one step, computed once and reused. The particles do not move between the
// P2G of step 1 and the velocity gradient of step 7 (positions advance only at the end of the
// step), so the shape functions at x^n that steps 1, 5, 6 and 7 of App. A.2 evaluate are the
// same four times. store_stencils (below; the engine's sort stage) stores them once and P2G,
// G2P, the MUSL remap and the velocity gradient read them back (kLoad); kCompute remains for
// callers without a cache. The four passes now use one set of weights per particle; before,
// each evaluated them in its own inlined code, where the compiler's FMA contraction of
// x / h - floor could differ in the last bits (docs/performance.md).
//
// kRecompute (uGIMP only, kRecomputedRows): nothing is stored; every read computes the row again
// from the positions and sizes (recomputed_rows, below), with the operations of store_stencils,
// so the same bits, and 145 B per particle less held through the step.
struct StencilCache {
  enum Mode : std::uint8_t { kCompute, kStore, kLoad, kRecompute };
  double* w = nullptr;          // per particle: w[3][W] then dw[3][W] (6 W doubles)
  std::uint8_t* off = nullptr;  // per particle: off[0] | off[1] << 2 | off[2] << 4
  Mode mode = kCompute;
  // kRecompute: what a row is computed from (store_stencils' arguments).
  const double* x[3] = {nullptr, nullptr, nullptr};
  const double* size0 = nullptr;
  double inv_h = 0.0;
  bool axisymmetric = false;
};

// The shapes whose rows the engine recomputes at every read instead of storing them.
template <class Shape>
inline constexpr bool kRecomputedRows = std::is_same_v<Shape, GimpShape>;

// One uGIMP row exactly as store_stencils<GimpShape> stores it, for one particle at a time:
// weights and derivatives of axis d at w[(d W + a) stride] and w[((3 + d) W + a) stride].
// The Release build contracted store_stencils' loop this way before the fusions were written out
// (found by comparing 2^20 random particles against the stored rows with every candidate): the
// first node (kernels::first_node), the remainder fma(x, 1/h, -fl) and d^2 + lp^2 as
// fma(d, d, lp^2), now explicit std::fma here and in GimpShape, and no other product meets a sum,
// so the bits do not depend on the compiler's contraction (tests/unit/mpm/stencil_cache_test.cpp
// keeps the check). Of the four pieces of GimpShape::node, the one that applies is selected before
// dividing (2 divisions per node instead of 4): the selected quotient has the same operands, so the
// same bits.
namespace gimp_rows {

inline int axis(double x, double inv_h, double lp, double* w, double* dw, int stride) {
  const double fl = first_node(x, inv_h, GimpShape::kShift);
  const double f = std::fma(x, inv_h, -fl);
  const double lp2 = lp * lp, two = 2.0 * lp, four = 4.0 * lp;
  for (int a = 0; a < 3; ++a) {
    const double d = f - a;
    const double ad = std::abs(d);
    const double s = d < 0.0 ? -1.0 : 1.0;
    const double r = 1.0 + lp - ad;
    const bool in = ad <= lp, mid = ad <= 1.0 - lp, out = ad <= 1.0 + lp;
    const double qw = (in ? std::fma(d, d, lp2) : r * r) / (in ? two : four);
    const double qd = (in ? -d : -s * r) / (in ? lp : two);
    w[a * stride] = in ? 1.0 - qw : mid ? 1.0 - ad : out ? qw : 0.0;
    dw[a * stride] = in ? qd : mid ? -s : out ? qd : 0.0;
  }
  return static_cast<int>(fl);
}

// Particle p's row (18 doubles at `row`, stride apart) and packed offsets.
inline std::uint8_t row(const StencilCache& c, std::size_t p, double* row, int stride) {
  constexpr int mask = 3;
  const double lp = std::min(0.5 * c.size0[p] * c.inv_h, 0.5);
  unsigned packed = 0;
  for (int d = 0; d < 3; ++d) {
    double* w = row + d * 3 * stride;
    double* dw = row + (9 + d * 3) * stride;
    if (c.axisymmetric && d == 1) {  // degenerate_weights
      for (int a = 0; a < 3; ++a) w[a * stride] = dw[a * stride] = 0.0;
      w[0] = 1.0;
      continue;
    }
    packed |= static_cast<unsigned>(axis(c.x[d][p], c.inv_h, lp, w, dw, stride) & mask) << (2 * d);
  }
  return static_cast<std::uint8_t>(packed);
}

}  // namespace gimp_rows

// Rows of up to kStencilBatch particles side by side: value j of the row (w[3][3], dw[3][3]) of
// the k-th particle at rows[j kStencilBatch + k].
inline constexpr int kStencilBatch = 8;

#if defined(SHATTER_AVX512_ROWS)
// gimp_rows in eight lanes, one particle per lane, each lane doing gimp_rows::axis's operations
// in its order (the same bits). Unaligned loads and stores throughout: GCC 12's AddressSanitizer
// places stack arrays at 32-byte boundaries whatever alignas asks (lanes.hpp, align64). The
// masked forms (all lanes) of min, roundscale and the conversions: GCC 12's unmasked ones start
// from _mm512_undefined_pd, which -Wmaybe-uninitialized reports.
namespace gimp_lanes {

// kernels::first_node in each lane: the same FMA, then the same floor.
inline __m512d first_node(__m512d x, __m512d inv_h, double shift) {
  return _mm512_maskz_roundscale_pd(0xFF, _mm512_fmadd_pd(x, inv_h, _mm512_set1_pd(-shift)),
                                    _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
}

// Positions (xv[3]) and sizes of particles idx[0..count); the tail lanes repeat the last one.
inline void load(const StencilCache& c, const std::uint32_t* idx, int count, __m512d (&xv)[3],
                 __m512d& sv) {
  bool consecutive = count == 8;  // the usual case: the store is sorted by block
  for (int k = 1; k < 8 && consecutive; ++k) consecutive = idx[k] == idx[0] + k;
  if (consecutive) {
    for (int d = 0; d < 3; ++d) xv[d] = _mm512_loadu_pd(c.x[d] + idx[0]);
    sv = _mm512_loadu_pd(c.size0 + idx[0]);
    return;
  }
  alignas(64) double xs[3][8], ss[8];
  for (int k = 0; k < 8; ++k) {
    const std::uint32_t p = idx[k < count ? k : count - 1];
    for (int d = 0; d < 3; ++d) xs[d][k] = c.x[d][p];
    ss[k] = c.size0[p];
  }
  for (int d = 0; d < 3; ++d) xv[d] = _mm512_loadu_pd(xs[d]);
  sv = _mm512_loadu_pd(ss);
}

// What gimp_rows::axis derives from lp alone: lp = min(size0 / (2 h), 1/2) (std::min's
// operand order: min(half, v) returns v unless half < v), lp^2, 2 lp, 4 lp, 1 + lp, 1 - lp.
struct HalfWidth {
  __m512d lp, lp2, two, four, opl, oml;
  HalfWidth(__m512d size0, __m512d inv_h) {
    const __m512d half = _mm512_set1_pd(0.5), one = _mm512_set1_pd(1.0);
    lp = _mm512_maskz_min_pd(0xFF, half, _mm512_mul_pd(_mm512_mul_pd(half, size0), inv_h));
    lp2 = _mm512_mul_pd(lp, lp);
    two = _mm512_mul_pd(_mm512_set1_pd(2.0), lp);
    four = _mm512_mul_pd(_mm512_set1_pd(4.0), lp);
    opl = _mm512_add_pd(one, lp);
    oml = _mm512_sub_pd(one, lp);
  }
};

// gimp_rows::axis for eight particles: weights to w[a * 8], derivatives (kGrad) to dw[a * 8];
// returns the first nodes' offsets in the owner block (2 bits per lane).
template <bool kGrad>
__m256i axis(__m512d x, __m512d inv_h, const HalfWidth& h, double* w, double* dw) {
  const __m512d one = _mm512_set1_pd(1.0), zero = _mm512_setzero_pd();
  const __m512d sign = _mm512_set1_pd(-0.0);  // -v as xor(v, sign): C's negation, zeros too
  const __m512d fl = first_node(x, inv_h, GimpShape::kShift);
  const __m512d f = _mm512_fmadd_pd(x, inv_h, _mm512_xor_pd(fl, sign));
  for (int a = 0; a < 3; ++a) {
    const __m512d dd = _mm512_sub_pd(f, _mm512_set1_pd(static_cast<double>(a)));
    const __m512d ad = _mm512_abs_pd(dd);
    const __mmask8 neg = _mm512_cmp_pd_mask(dd, zero, _CMP_LT_OQ);
    const __m512d ms = _mm512_mask_blend_pd(neg, _mm512_set1_pd(-1.0), one);  // -s
    const __m512d r = _mm512_sub_pd(h.opl, ad);
    const __mmask8 in = _mm512_cmp_pd_mask(ad, h.lp, _CMP_LE_OQ);
    const __mmask8 mid = _mm512_cmp_pd_mask(ad, h.oml, _CMP_LE_OQ);
    const __mmask8 out = _mm512_cmp_pd_mask(ad, h.opl, _CMP_LE_OQ);
    const __m512d qw =
        _mm512_div_pd(_mm512_mask_blend_pd(in, _mm512_mul_pd(r, r), _mm512_fmadd_pd(dd, dd, h.lp2)),
                      _mm512_mask_blend_pd(in, h.four, h.two));
    __m512d wv = _mm512_maskz_mov_pd(out, qw);
    wv = _mm512_mask_blend_pd(mid, wv, _mm512_sub_pd(one, ad));
    wv = _mm512_mask_blend_pd(in, wv, _mm512_sub_pd(one, qw));
    _mm512_storeu_pd(w + a * 8, wv);
    if constexpr (!kGrad) continue;
    const __m512d qd =
        _mm512_div_pd(_mm512_mask_blend_pd(in, _mm512_mul_pd(ms, r), _mm512_xor_pd(dd, sign)),
                      _mm512_mask_blend_pd(in, h.two, h.lp));
    __m512d dv = _mm512_maskz_mov_pd(out, qd);
    dv = _mm512_mask_blend_pd(mid, dv, ms);
    dv = _mm512_mask_blend_pd(in, dv, qd);
    _mm512_storeu_pd(dw + a * 8, dv);
  }
  return _mm256_and_si256(_mm512_maskz_cvttpd_epi32(0xFF, fl), _mm256_set1_epi32(3));
}

}  // namespace gimp_lanes
#endif

// The rows of particles idx[0..count) (count <= kStencilBatch). With AVX-512, eight particles
// per vector (gimp_lanes); otherwise particle by particle (gimp_rows).
// kGrad false: the weights alone (G2P, the remap's scatter), the derivatives left as they were.
template <bool kGrad = true>
inline void recomputed_rows(const StencilCache& c, const std::uint32_t* idx, int count,
                            double* rows, std::uint8_t* off) {
#if defined(SHATTER_AVX512_ROWS)
  static_assert(kStencilBatch == 8);
  __m512d xv[3], sv;
  gimp_lanes::load(c, idx, count, xv, sv);
  const __m512d ih = _mm512_set1_pd(c.inv_h);
  const gimp_lanes::HalfWidth hw(sv, ih);
  __m256i packed = _mm256_setzero_si256();
  for (int d = 0; d < 3; ++d) {
    double* w = rows + d * 3 * 8;
    double* dw = rows + (9 + d * 3) * 8;
    if (c.axisymmetric && d == 1) {  // degenerate_weights, offset 0
      for (int a = 0; a < 3; ++a) {
        _mm512_storeu_pd(w + a * 8, _mm512_set1_pd(a == 0 ? 1.0 : 0.0));
        _mm512_storeu_pd(dw + a * 8, _mm512_setzero_pd());
      }
      continue;
    }
    const __m256i first = gimp_lanes::axis<kGrad>(xv[d], ih, hw, w, dw);
    packed = _mm256_or_si256(packed, _mm256_sllv_epi32(first, _mm256_set1_epi32(2 * d)));
  }
  alignas(16) std::uint8_t o[16];
  _mm_storeu_si128(reinterpret_cast<__m128i*>(o), _mm256_maskz_cvtepi32_epi8(0xFF, packed));
  for (int k = 0; k < count; ++k) off[k] = o[k];
#else
  for (int k = 0; k < count; ++k) off[k] = gimp_rows::row(c, idx[k], rows + k, kStencilBatch);
#endif
}

template <class Shape>
struct Stencil {
  static constexpr int W = Shape::kWidth;
  double w[3][W];         // shape value per axis and node
  double dw[3][W];        // derivative per axis and node, in 1/cell units (multiply by 1/h)
  int off[3];             // first stencil node relative to the owner block's first node (0..3)
  std::int64_t first[3];  // first stencil node, global index per axis

  // x: the particle's position (metres, or cell units with inv_h = 1). half_size: uGIMP
  // particle half-width in cell units, clamped to 1/2 so that the support stays within three
  // nodes.
  void compute(const double x[3], double inv_h, double half_size, const SparseGrid::Coord& owner) {
    const double lp = std::min(half_size, 0.5);
    const int base[3] = {owner.x * SparseGrid::kBlock, owner.y * SparseGrid::kBlock,
                         owner.z * SparseGrid::kBlock};
    for (int d = 0; d < 3; ++d) {
      first[d] = Shape::weights(x[d], inv_h, lp, w[d], dw[d]);
      off[d] = static_cast<int>(first[d] - base[d]);
    }
  }

  static constexpr int kRow = 6 * W;  // doubles per particle in a StencilCache

  // Weights, derivatives and the packed node offsets of one row (stored or recomputed).
  void from_row(const double* row, unsigned packed, const SparseGrid::Coord& owner) {
    std::copy(row, row + 3 * W, &w[0][0]);
    std::copy(row + 3 * W, row + kRow, &dw[0][0]);
    const int base[3] = {owner.x * SparseGrid::kBlock, owner.y * SparseGrid::kBlock,
                         owner.z * SparseGrid::kBlock};
    for (int d = 0; d < 3; ++d) {
      off[d] = static_cast<int>((packed >> (2 * d)) & 3U);
      first[d] = base[d] + off[d];
    }
  }

  // The stencil of particle p: computed, computed and stored, or loaded (StencilCache::Mode).
  void prepare(const StencilCache& cache, std::size_t p, const double x[3], double inv_h,
               double half_size, const SparseGrid::Coord& owner) {
    if (cache.mode == StencilCache::kLoad) {
      from_row(cache.w + p * kRow, cache.off[p], owner);
      return;
    }
    if constexpr (kRecomputedRows<Shape>) {
      if (cache.mode == StencilCache::kRecompute) {  // the row store_stencils would store
        double row[kRow];
        const unsigned o = gimp_rows::row(cache, p, row, 1);
        from_row(row, o, owner);
        return;
      }
    }
    compute(x, inv_h, half_size, owner);
    if (cache.mode == StencilCache::kStore) {
      double* row = cache.w + p * kRow;
      std::copy(&w[0][0], &w[0][0] + 3 * W, row);
      std::copy(&dw[0][0], &dw[0][0] + 3 * W, row + 3 * W);
      cache.off[p] = static_cast<std::uint8_t>(off[0] | (off[1] << 2) | (off[2] << 4));
    }
  }

  // Node minus particle position along axis d for stencil node a, in metres (APIC's x_i - x_p).
  double offset(int d, int a, double xi_d, double h) const {
    return (static_cast<double>(first[d] + a) - xi_d) * h;
  }

  // Global node index of stencil node (a, b, c).
  std::uint32_t node(const std::uint32_t* neighbours, int a, int b, int c) const {
    const int lx = off[0] + a, ly = off[1] + b, lz = off[2] + c;
    const int s = (lx >> SparseGrid::kBlockBits) | ((ly >> SparseGrid::kBlockBits) << 1) |
                  ((lz >> SparseGrid::kBlockBits) << 2);
    constexpr int m = SparseGrid::kBlock - 1;
    return neighbours[s] * SparseGrid::kBlockNodes + SparseGrid::local(lx & m, ly & m, lz & m);
  }
};

// A stored stencil read in place (StencilCache::kLoad): particle p's weights and derivatives
// straight from its cache row, with no copy into a Stencil. Stencil::prepare copies the row with
// vector stores, and the gathers' scalar loads of single weights right after cannot be forwarded
// from a wider store (the likely cause): they wait for the store to retire. Read in place, the
// velocity gradient's arithmetic core (bench/transfer_lanes.cpp) takes 25 instead of 49 ns per
// particle, G2P's 20 instead of 25 (docs/performance.md, "MPM transfers, round 4"). Same values,
// same operations: the same bits.
template <class Shape>
struct StoredStencil {
  static constexpr int W = Shape::kWidth;
  const double (*w)[W];   // w[3][W] of the row
  const double (*dw)[W];  // dw[3][W] of the row
  int off[3];             // as Stencil::off

  StoredStencil(const StencilCache& cache, std::size_t p)
      : w(reinterpret_cast<const double (*)[W]>(cache.w + p * Stencil<Shape>::kRow)),
        dw(reinterpret_cast<const double (*)[W]>(cache.w + p * Stencil<Shape>::kRow + 3 * W)) {
    const unsigned o = cache.off[p];
    for (int d = 0; d < 3; ++d) off[d] = static_cast<int>((o >> (2 * d)) & 3U);
  }
};

// A recomputed row read where recomputed_rows put it (kStencilBatch apart): st.w[d][a] and
// st.dw[d][a] as for a StoredStencil.
template <class Shape>
struct BatchStencil {
  static constexpr int W = Shape::kWidth;
  struct Axis {
    const double* p;
    double operator[](int a) const { return p[a * kStencilBatch]; }
  };
  struct Table {
    const double* p;
    Axis operator[](int d) const { return {p + d * W * kStencilBatch}; }
  };
  Table w, dw;
  int off[3];
  BatchStencil(const double* rows, int k, std::uint8_t o)
      : w{rows + k}, dw{rows + 3 * W * kStencilBatch + k} {
    for (int d = 0; d < 3; ++d) off[d] = static_cast<int>((o >> (2 * d)) & 3U);
  }
};

// body(stencil, p) for every particle p of `particles` in order, with its row recomputed
// (kRecompute, kRecomputedRows<Shape>) kStencilBatch particles at a time; kGrad false: the
// weights only (the derivatives read as zero).
template <class Shape, bool kGrad = true, class Body>
void for_each_recomputed(const StencilCache& cache, std::span<const std::uint32_t> particles,
                         Body&& body) {
  static_assert(kRecomputedRows<Shape>);
  alignas(64) double rows[Stencil<Shape>::kRow * kStencilBatch] = {};
  std::uint8_t off[kStencilBatch];
  for (std::size_t k0 = 0; k0 < particles.size(); k0 += kStencilBatch) {
    const int count = static_cast<int>(std::min<std::size_t>(kStencilBatch, particles.size() - k0));
    recomputed_rows<kGrad>(cache, particles.data() + k0, count, rows, off);
    for (int k = 0; k < count; ++k) body(BatchStencil<Shape>(rows, k, off[k]), particles[k0 + k]);
  }
}

// Global node index of stencil node (a, b, c) of a Stencil or a StoredStencil (Stencil::node).
template <class St>
std::uint32_t node_index(const St& st, const std::uint32_t* neighbours, int a, int b, int c) {
  const int lx = st.off[0] + a, ly = st.off[1] + b, lz = st.off[2] + c;
  const int s = (lx >> SparseGrid::kBlockBits) | ((ly >> SparseGrid::kBlockBits) << 1) |
                ((lz >> SparseGrid::kBlockBits) << 2);
  constexpr int m = SparseGrid::kBlock - 1;
  return neighbours[s] * SparseGrid::kBlockNodes + SparseGrid::local(lx & m, ly & m, lz & m);
}

// The degenerate axis of the axisymmetric mode: node 0 with weight 1, derivative 0.
template <int W>
int degenerate_weights(double (&w)[W], double (&dw)[W]) {
  for (int a = 0; a < W; ++a) w[a] = dw[a] = 0.0;
  w[0] = 1.0;
  return 0;
}

// Stores the stencils of particles [begin, end) in `cache` (StencilCache layout), straight from
// the positions: the offset of the first node inside its owner block is its global index modulo
// kBlock, since the owner block is the block of the first node (SparseGrid). One streaming pass
// over the particles, vectorisable, instead of four evaluations inside the transfer loops.
//
// kAxisymmetric (SolverConfig::Geometry): the y axis is degenerate, every point at y = 0 and its
// y stencil the single node y = 0 with weight 1 and derivative 0 (the other W - 1 entries of
// weight 0 add nothing). The grid is then one layer of nodes in (x, z) = (r, z), and every
// transfer that reads the cache (P2G, G2P, remap, filters, velocity gradient) works in r-z.
template <class Shape, bool kAxisymmetric = false>
void store_stencils(const double* const (&x)[3], const double* size0, double inv_h,
                    std::size_t begin, std::size_t end, const StencilCache& cache) {
  constexpr int W = Shape::kWidth;
  constexpr int mask = SparseGrid::kBlock - 1;
  for (std::size_t p = begin; p < end; ++p) {
    const double lp = std::min(0.5 * size0[p] * inv_h, 0.5);
    double* row = cache.w + p * Stencil<Shape>::kRow;
    unsigned packed = 0;
    for (int d = 0; d < 3; ++d) {
      double w[W], dw[W];
      const int first = kAxisymmetric && d == 1 ? degenerate_weights<W>(w, dw)
                                                : Shape::weights(x[d][p], inv_h, lp, w, dw);
      for (int a = 0; a < W; ++a) {
        row[d * W + a] = w[a];
        row[(3 + d) * W + a] = dw[a];
      }
      packed |= static_cast<unsigned>(first & mask) << (2 * d);
    }
    cache.off[p] = static_cast<std::uint8_t>(packed);
  }
}

// The nodes of the 2x2x2 blocks that the stencils of one owner block reach, copied into one
// padded cube of (kBlock + 2)^3 nodes (the reverse of P2GScratch's flush in p2g.hpp). A gather
// (G2P, velocity gradient) then finds stencil node (a, b, c) at a fixed stride, with no block
// lookup per node. WindowGeometry is the cube; NodeWindow holds F fields one after the other,
// G2PWindow (g2p.hpp) the fields of each node side by side.
struct WindowGeometry {
  static constexpr int kEdge = SparseGrid::kBlock + 2;
  static constexpr int kSize = kEdge * kEdge * kEdge;

  // body(i, g) for every window node i and its grid node g, through the owner's neighbour list
  // (8 blocks).
  template <class Body>
  static void visit(const std::uint32_t* neighbours, Body&& body) {
    constexpr int mask = SparseGrid::kBlock - 1;
    constexpr int bits = SparseGrid::kBlockBits;
    for (int lx = 0; lx < kEdge; ++lx) {
      for (int ly = 0; ly < kEdge; ++ly) {
        const int sel_xy = (lx >> bits) | ((ly >> bits) << 1);
        for (int lz = 0; lz < kEdge; ++lz) {
          const int i = (lx * kEdge + ly) * kEdge + lz;
          const std::size_t g =
              std::size_t{neighbours[sel_xy | ((lz >> bits) << 2)]} * SparseGrid::kBlockNodes +
              static_cast<std::size_t>(SparseGrid::local(lx & mask, ly & mask, lz & mask));
          body(i, g);
        }
      }
    }
  }

  // Window index of stencil node (a, b, 0); node (a, b, c) is at row(st, a, b) + c. St: a
  // Stencil or a StoredStencil.
  template <class St>
  static int row(const St& st, int a, int b) {
    return ((st.off[0] + a) * kEdge + (st.off[1] + b)) * kEdge + st.off[2];
  }
};

// F node fields, one array each.
template <int F>
struct NodeWindow : WindowGeometry {
  double v[F][kSize];

  // Copies `count` (<= F) node fields.
  void load(const std::uint32_t* neighbours, const double* const* fields, int count) {
    visit(neighbours, [&](int i, std::size_t g) {
      for (int f = 0; f < count; ++f) v[f][i] = fields[f][g];
    });
  }
};

}  // namespace shatter::kernels
