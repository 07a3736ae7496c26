// P2G (App. A.2 steps 1 and 3): scatter of mass, momentum and internal force to the sparse grid,
// colour by colour, through kernels::p2g_block, exactly as the engine's p2g stage runs it
// (including the clear of the node arrays).
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

BENCHMARK_MAIN();
