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

// The engine's uGIMP P2G (rows recomputed at each read, StencilCache::kRecompute) with kStreams
// interleaved streams (kernels::p2g_block): 1 = the list order of main before session 21. The
// streams alternate inside one process (range 2), so their ratio is taken under one load.
template <int kStreams>
void scatter_recomputed(kernels::P2GParticles& in, SparseGrid& grid) {
  bench::scatter<kernels::GimpShape, true, kStreams>(in, grid);
}

void BM_P2GStreams(benchmark::State& state) {
  bench::Prepared<kernels::GimpShape> body(state.range(0));
  auto in = bench::p2g_inputs(body.store, true);
  const ParticleStore& P = body.store;
  in.stencil.mode = kernels::StencilCache::kRecompute;
  in.stencil.x[0] = P.col(Field::x).data();
  in.stencil.x[1] = P.col(Field::y).data();
  in.stencil.x[2] = P.col(Field::z).data();
  in.stencil.size0 = P.col(Field::size0).data();
  in.stencil.inv_h = in.inv_h;
  const auto streams = state.range(2);
  tbb::task_arena arena(static_cast<int>(state.range(1)));
  arena.execute([&] {
    for (auto _ : state) {
      if (streams == 1) scatter_recomputed<1>(in, body.grid);
      if (streams == 2) scatter_recomputed<2>(in, body.grid);
      if (streams == 3) scatter_recomputed<3>(in, body.grid);
      if (streams == 4) scatter_recomputed<4>(in, body.grid);
      benchmark::ClobberMemory();
    }
  });
  bench::report(state, body.store, body.grid.bytes());
}

}  // namespace

BENCHMARK(BM_P2GStreams)
    ->Name("p2g/ugimp_recomputed")
    ->ArgNames({"particles", "threads", "streams"})
    ->ArgsProduct({{100'000, 1'000'000}, {1}, {1, 2, 3, 4}})
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
