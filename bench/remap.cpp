// MUSL remap (App. A.2 step 6): the updated particle momentum scattered back to the grid
// (kernels::p2g_block without force), then the engine's own Boundaries pass (mirror, constraints,
// v_I = P_I / M_I) on an open domain, as the engine's remap stage runs it.
#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include "shatter/mpm/boundaries.hpp"  // the real nodal pass, not a copy
#include "support/stages.hpp"

namespace {

using namespace shatter;

template <class Shape>
void BM_Remap(benchmark::State& state) {
  bench::Prepared<Shape> body(state.range(0));
  auto in = bench::p2g_inputs(body.store, false);
  in.stencil = body.stencils(kernels::StencilCache::kLoad);  // as the engine's remap
  tbb::task_arena arena(static_cast<int>(state.range(1)));
  const mpm::Boundaries boundaries(Domain{}, bench::kCell);
  const double empty_mass = 1e-12 * body.store.col(Field::mass)[0];
  arena.execute([&] {
    for (auto _ : state) {
      bench::scatter<Shape, false>(in, body.grid);
      boundaries.mirror(body.grid, mpm::Boundaries::kMomentum);
      benchmark::DoNotOptimize(boundaries.velocities(body.grid, empty_mass));
      benchmark::ClobberMemory();
    }
  });
  bench::report(state, body.store, body.grid.bytes());
  state.counters["col_bytes_read"] = 8.0 * 9;  // x, v, mass, rho, size0
}

}  // namespace

BENCHMARK(BM_Remap<kernels::GimpShape>)->Name("remap/ugimp")->Apply(bench::sizes_and_threads);

BENCHMARK_MAIN();
