// Grid update (App. A.2 steps 2-4): symmetry mirror, gravity, constraints and the nodal momentum
// update P += F dt with F/M and P/M left in the node arrays, through the engine's own Boundaries
// (an engine-internal header). Open domain (the common case) and a box of slip walls on all six
// faces (every node runs the constraint test). Items are particles, so that figures compare with
// the other stages; nodes/particle says how many nodes each particle brings.
#include <vector>

#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include "shatter/mpm/boundaries.hpp"
#include "support/stages.hpp"

namespace {

using namespace shatter;

template <class Shape>
void BM_GridUpdate(benchmark::State& state, bool walls) {
  bench::Prepared<Shape> body(state.range(0));
  SparseGrid& grid = body.grid;
  // Scatter again (Prepared left velocities in the grid) and keep a copy of the scattered state
  // to restore, untimed, before each update.
  bench::scatter<Shape, true>(bench::p2g_inputs(body.store, true), grid);
  const SparseGrid::Nodes scattered = grid.nodes();
  Domain domain;
  if (walls) {
    domain.lo = Vec3::Constant(-1.0);
    domain.hi = Vec3::Constant(2.0);
    domain.faces.fill(BoundaryKind::slip);
  }
  const mpm::Boundaries boundaries(domain, bench::kCell);
  const Vec3 gravity(0.0, 0.0, -9.81);
  const double empty_mass = 1e-12 * body.store.col(Field::mass)[0];
  tbb::task_arena arena(static_cast<int>(state.range(1)));
  arena.execute([&] {
    for (auto _ : state) {
      state.PauseTiming();
      grid.nodes() = scattered;
      state.ResumeTiming();
      boundaries.mirror(grid, mpm::Boundaries::kMassMomentumForce);
      benchmark::DoNotOptimize(boundaries.integrate(grid, gravity, 1e-7, empty_mass));
      benchmark::ClobberMemory();
    }
  });
  bench::report(state, body.store, grid.bytes());
  state.counters["nodes/particle"] =
      static_cast<double>(grid.nodes().mass.size()) / static_cast<double>(body.store.size());
}

void BM_GridUpdateOpen(benchmark::State& state) {
  BM_GridUpdate<kernels::GimpShape>(state, false);
}
void BM_GridUpdateWalls(benchmark::State& state) {
  BM_GridUpdate<kernels::GimpShape>(state, true);
}

}  // namespace

BENCHMARK(BM_GridUpdateOpen)->Name("grid_update/open")->Apply(shatter::bench::sizes_and_threads);
BENCHMARK(BM_GridUpdateWalls)
    ->Name("grid_update/slip_walls")
    ->Apply(shatter::bench::sizes_and_threads);

BENCHMARK_MAIN();
