// P2G (App. A.2 steps 1 and 3): scatter of mass, momentum and internal force to the sparse grid,
// colour by colour, through kernels::p2g_block, exactly as the engine's p2g stage runs it
// (including the clear of the node arrays).
#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include "support/stages.hpp"

namespace {

using namespace shatter;

template <class Shape>
void BM_P2G(benchmark::State& state) {
  bench::Prepared<Shape> body(state.range(0));
  auto in = bench::p2g_inputs(body.store, true);
  in.stencil = body.stencils(kernels::StencilCache::kLoad);  // as the engine's P2G
  tbb::task_arena arena(static_cast<int>(state.range(1)));
  arena.execute([&] {
    for (auto _ : state) {
      bench::scatter<Shape, true>(in, body.grid);
      benchmark::ClobberMemory();
    }
  });
  bench::report(state, body.store, body.grid.bytes());
  // Particle columns the stage reads (x, v, mass, rho, size0, stress), per particle.
  state.counters["col_bytes_read"] = 8.0 * 15;
  state.counters["blocks"] = static_cast<double>(body.grid.blocks());
}

// The engine's uGIMP P2G (rows recomputed at each read, StencilCache::kRecompute; BM_P2G reads
// stored rows), or the stored rows (range 2 = 0), each with the node factors of a stencil taken
// from a table filled four nodes per vector (kernels::NodeFactors; range 3 = 1) or as products in
// the node loop (0, main before session 21: the same bits). Run with
// --benchmark_enable_random_interleaving: the variants alternate inside one process, so their
// ratio is taken under one load.
void BM_P2GFactors(benchmark::State& state) {
  bench::Prepared<kernels::GimpShape> body(state.range(0));
  auto in = bench::p2g_inputs(body.store, true);
  in.stencil = body.stencils(kernels::StencilCache::kLoad);
  if (state.range(2) == 1) {
    const ParticleStore& P = body.store;
    in.stencil.mode = kernels::StencilCache::kRecompute;
    in.stencil.x[0] = P.col(Field::x).data();
    in.stencil.x[1] = P.col(Field::y).data();
    in.stencil.x[2] = P.col(Field::z).data();
    in.stencil.size0 = P.col(Field::size0).data();
    in.stencil.inv_h = in.inv_h;
  }
  const bool table = state.range(3) == 1;
  tbb::task_arena arena(static_cast<int>(state.range(1)));
  arena.execute([&] {
    for (auto _ : state) {
      if (table) {
        bench::scatter<kernels::GimpShape, true, true>(in, body.grid);
      } else {
        bench::scatter<kernels::GimpShape, true, false>(in, body.grid);
      }
      benchmark::ClobberMemory();
    }
  });
  bench::report(state, body.store, body.grid.bytes());
}

#if defined(SHATTER_AVX512_ROWS)
// Session 23 trial (docs/performance.md, "Session 23: MPM transfers"): P2G with the particles
// that share a stencil in the lanes of one vector, per node the eight lanes' contributions
// reduced by a fixed transpose-add tree (round-off against the engine's particle-by-particle
// sums; not in the engine). r[f] = sum over the lanes of v[f].
inline __m512d lane_sums(const __m512d (&v)[8]) {
  __m512d t[4];
  for (int k = 0; k < 4; ++k) {
    t[k] = _mm512_add_pd(_mm512_maskz_unpacklo_pd(0xFF, v[2 * k], v[2 * k + 1]),
                         _mm512_maskz_unpackhi_pd(0xFF, v[2 * k], v[2 * k + 1]));
  }
  const __m512d s01 = _mm512_add_pd(_mm512_maskz_shuffle_f64x2(0xFF, t[0], t[1], 0x88),
                                    _mm512_maskz_shuffle_f64x2(0xFF, t[0], t[1], 0xDD));
  const __m512d s23 = _mm512_add_pd(_mm512_maskz_shuffle_f64x2(0xFF, t[2], t[3], 0x88),
                                    _mm512_maskz_shuffle_f64x2(0xFF, t[2], t[3], 0xDD));
  return _mm512_add_pd(_mm512_maskz_shuffle_f64x2(0xFF, s01, s23, 0x88),
                       _mm512_maskz_shuffle_f64x2(0xFF, s01, s23, 0xDD));
}

// One run of up to eight particles idx[0..count) with the stencil base `base`, the force scatter.
void p2g_shared_run(const kernels::P2GParticles& in, const std::uint32_t* idx, int count,
                    unsigned base, kernels::P2GScratch& s) {
  constexpr int B = kernels::kStencilBatch, E = kernels::P2GScratch::kEdge;
  alignas(64) double rows[18 * B] = {};
  std::uint8_t off[B];
  kernels::recomputed_rows<true>(in.stencil, idx, count, rows, off);
  alignas(64) double f[10][B] = {};  // m, m v, -V sigma / h (xx, yy, zz, xy, yz, xz)
  for (int k = 0; k < count; ++k) {
    const kernels::P2GPoint q = kernels::p2g_point<true>(in, idx[k]);
    const double v[10] = {q.m, q.mvx, q.mvy, q.mvz, q.sxx, q.syy, q.szz, q.sxy, q.syz, q.sxz};
    for (int j = 0; j < 10; ++j) f[j][k] = v[j];
  }
  __m512d F[10];
  for (int j = 0; j < 10; ++j) F[j] = _mm512_load_pd(f[j]);
  const auto w = [&](int d, int a) { return _mm512_load_pd(rows + (3 * d + a) * B); };
  const auto dw = [&](int d, int a) { return _mm512_load_pd(rows + (9 + 3 * d + a) * B); };
  const int o[3] = {static_cast<int>(base & 3U), static_cast<int>((base >> 2) & 3U),
                    static_cast<int>((base >> 4) & 3U)};
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) {
      const __m512d wab = _mm512_mul_pd(w(0, a), w(1, b));
      const __m512d gxab = _mm512_mul_pd(dw(0, a), w(1, b));
      const __m512d gyab = _mm512_mul_pd(w(0, a), dw(1, b));
      const int row = ((o[0] + a) * E + (o[1] + b)) * E + o[2];
      for (int c = 0; c < 3; ++c) {
        const __m512d N = _mm512_mul_pd(wab, w(2, c));
        const __m512d gx = _mm512_mul_pd(gxab, w(2, c)), gy = _mm512_mul_pd(gyab, w(2, c));
        const __m512d gz = _mm512_mul_pd(wab, dw(2, c));
        const __m512d v[8] = {
            _mm512_mul_pd(F[0], N),
            _mm512_mul_pd(F[1], N),
            _mm512_mul_pd(F[2], N),
            _mm512_mul_pd(F[3], N),
            _mm512_fmadd_pd(F[9], gz, _mm512_fmadd_pd(F[4], gx, _mm512_mul_pd(F[7], gy))),
            _mm512_fmadd_pd(F[8], gz, _mm512_fmadd_pd(F[7], gx, _mm512_mul_pd(F[5], gy))),
            _mm512_fmadd_pd(F[6], gz, _mm512_fmadd_pd(F[9], gx, _mm512_mul_pd(F[8], gy))),
            _mm512_setzero_pd()};
        double* node = s.q(row + c);
        _mm512_store_pd(node, _mm512_add_pd(_mm512_load_pd(node), lane_sums(v)));
      }
    }
  }
}

// The trial's P2G over every block, colour by colour as the engine: the block's list cut into
// runs of up to eight consecutive particles with one stencil base.
void p2g_shared(const kernels::P2GParticles& in, SparseGrid& grid,
                const std::vector<std::uint8_t>& bases) {
  grid.clear_nodes();
  for (int c = 0; c < SparseGrid::kColours; ++c) {
    const auto blocks = grid.colour(c);
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, blocks.size(), 1),
        [&](const tbb::blocked_range<std::size_t>& r) {
          kernels::P2GScratch scratch;
          for (std::size_t k = r.begin(); k < r.end(); ++k) {
            const auto list = grid.owned(blocks[k]);
            kernels::p2g_clear<true, true>(scratch);
            for (std::size_t i = 0; i < list.size();) {
              std::size_t j = i + 1;
              while (j < list.size() && j - i < 8 && bases[list[j]] == bases[list[i]]) {
                ++j;
              }
              p2g_shared_run(in, list.data() + i, static_cast<int>(j - i), bases[list[i]], scratch);
              i = j;
            }
            kernels::p2g_flush<true, true>(scratch, grid.neighbours(blocks[k]), grid.nodes());
          }
        });
  }
}

// range 2 = 0: the engine's P2G (recomputed rows, node factor table) on the engine's order (list
// by id); 1: the trial, on a store and lists ordered by (block, stencil base). Both in one
// process; the node mass and force sums of the two are compared once (round-off apart).
void BM_P2GSharedTrial(benchmark::State& state) {
  using Shape = kernels::GimpShape;
  bench::Prepared<Shape> body(state.range(0));
  ParticleStore& P = body.store;
  const std::size_t n = P.size();
  const double ih = 1.0 / bench::kCell;
  std::vector<std::uint8_t> bases(n);
  std::vector<std::uint64_t> keys;
  const bool shared = state.range(2) == 1;
  SparseGrid by_base;
  if (shared) {
    const double* X[3] = {P.col(Field::x).data(), P.col(Field::y).data(), P.col(Field::z).data()};
    for (std::size_t p = 0; p < n; ++p) {
      unsigned b = 0;
      for (int d = 0; d < 3; ++d) {
        const auto fl = static_cast<std::int64_t>(kernels::first_node(X[d][p], ih, 0.5));
        b |= static_cast<unsigned>(fl & 3) << (2 * d);
      }
      bases[p] = static_cast<std::uint8_t>(b);
    }
    bench::owner_keys<Shape>(P, keys);
    std::vector<std::uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0U);
    std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
      return keys[a] != keys[b] ? keys[a] < keys[b] : bases[a] < bases[b];
    });
    P.permute(order);
    std::vector<std::uint8_t> sorted(n);
    for (std::size_t k = 0; k < n; ++k) sorted[k] = bases[order[k]];
    bases.swap(sorted);
    bench::owner_keys<Shape>(P, keys);
    by_base.assign(keys);  // lists in store order: by (block, base)
  }
  SparseGrid& grid = shared ? by_base : body.grid;
  auto in = bench::p2g_inputs(P, true);
  in.stencil.mode = kernels::StencilCache::kRecompute;
  in.stencil.x[0] = P.col(Field::x).data();
  in.stencil.x[1] = P.col(Field::y).data();
  in.stencil.x[2] = P.col(Field::z).data();
  in.stencil.size0 = P.col(Field::size0).data();
  in.stencil.inv_h = ih;
  tbb::task_arena arena(static_cast<int>(state.range(1)));
  arena.execute([&] {
    for (auto _ : state) {
      if (shared) {
        p2g_shared(in, grid, bases);
      } else {
        bench::scatter<Shape, true>(in, grid);
      }
      benchmark::ClobberMemory();
    }
  });
  double sums[4] = {};
  for (std::size_t i = 0; i < grid.nodes().mass.size(); ++i) {
    sums[0] += grid.nodes().mass[i], sums[1] += grid.nodes().px[i];
    sums[2] += std::abs(grid.nodes().fx[i]), sums[3] += std::abs(grid.nodes().fz[i]);
  }
  state.counters["sum_mass"] = sums[0];
  state.counters["sum_px"] = sums[1];
  state.counters["sum_abs_fx"] = sums[2];
  state.counters["sum_abs_fz"] = sums[3];
  bench::report(state, P, grid.bytes());
}
#endif

}  // namespace

BENCHMARK(BM_P2GFactors)
    ->Name("p2g/ugimp_factors")
    ->ArgNames({"particles", "threads", "recomputed", "table"})
    ->ArgsProduct({bench::particle_counts({100'000, 1'000'000}), {1}, {0, 1}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MeasureProcessCPUTime();
BENCHMARK(BM_P2G<kernels::GimpShape>)->Name("p2g/ugimp")->Apply(bench::sizes_and_threads);
BENCHMARK(BM_P2G<kernels::LinearShape>)
    ->Name("p2g/linear")
    ->Apply(bench::one_thread)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MeasureProcessCPUTime();
BENCHMARK(BM_P2G<kernels::BSpline2Shape>)
    ->Name("p2g/bspline2")
    ->Apply(bench::one_thread)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MeasureProcessCPUTime();

#if defined(SHATTER_AVX512_ROWS)
BENCHMARK(BM_P2GSharedTrial)
    ->Name("p2g/ugimp_shared_trial")
    ->ArgsProduct({bench::particle_counts({100000, 1000000}), {1}, {0, 1}})
    ->ArgNames({"particles", "threads", "shared"});
#endif

BENCHMARK_MAIN();
