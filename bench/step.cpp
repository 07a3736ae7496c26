// The whole elastic MUSL step, Simulation::step(): sort, P2G, grid update, G2P, remap, velocity
// gradient, linear elastic update, position update, energy sums and the next time step, as the
// stage graph runs them. The body drifts at 1 km/s (an impactor's speed), so that particles
// change owner block every step and the sparse grid is rebuilt every step, as in an impact; the
// physical re-order of the columns (every 25 steps) falls in the untimed warm-up step and is
// timed alone in bench_sort (sort/reorder).
//
// Counters: items/s = particle-steps per second; bytes/particle = registered particle columns +
// Simulation::grid_bytes() / particles; <stage>_ns = wall time of that stage per particle-step
// from Simulation::stage_timings() (stages overlap only where the graph lets them: energy and
// time_step).
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "shatter/engine/simulation.hpp"
#include "shatter/material/linear_elastic.hpp"
#include "support/bodies.hpp"

namespace {

using namespace shatter;

constexpr double kDrift = 1000.0;  // m/s

void BM_Step(benchmark::State& state, ShapeKind shape) {
  const auto threads = static_cast<int>(state.range(1));
  SolverConfig cfg;
  cfg.shape = shape;
  cfg.cell_size = bench::kCell;
  std::vector<MaterialPtr> materials{
      std::make_shared<LinearElastic>(bench::kRho, bench::kYoung, bench::kPoisson)};
  Simulation sim(cfg, bench::make_body(state.range(0), kDrift), std::move(materials), threads);
  sim.step();  // warm-up: first allocation of the grid and the step-0 column re-order
  const std::vector<StageTiming> before = sim.stage_timings();
  for (auto _ : state) sim.step();
  const std::vector<StageTiming>& after = sim.stage_timings();

  const double n = static_cast<double>(sim.particles().size());
  bench::report(state, sim.particles(), sim.grid_bytes());
  const double steps = static_cast<double>(state.iterations());
  for (std::size_t s = 0; s < after.size(); ++s) {
    const double ns = 1e9 * (after[s].seconds - before[s].seconds) / (steps * n);
    state.counters[after[s].name + "_ns"] = ns;
  }
  state.counters["blocks"] = static_cast<double>(sim.active_blocks());
}

void steps(benchmark::internal::Benchmark* b) {
  bench::sizes_and_threads(b);
}

}  // namespace

BENCHMARK_CAPTURE(BM_Step, ugimp, ShapeKind::ugimp)->Apply(steps);
BENCHMARK_CAPTURE(BM_Step, linear, ShapeKind::linear)->Apply(steps);
BENCHMARK_CAPTURE(BM_Step, bspline2, ShapeKind::bspline2)->Apply(steps);

BENCHMARK_MAIN();
