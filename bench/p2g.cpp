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

}  // namespace

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
