// The whole elastic MUSL step, Simulation::step(): sort, P2G, grid update, G2P, remap, velocity
// gradient, linear elastic update, position update, energy sums and the next time step, as the
// stage graph runs them. The body drifts at 1 km/s (an impactor's speed), so that particles
// change owner block every step and the sparse grid is rebuilt every step, as in an impact; the
// physical re-order of the columns (every 25 steps) falls in the untimed warm-up step and is
// timed alone in bench_sort (sort/reorder).
//
// Counters: items/s = particle-steps per second; bytes/particle = registered particle columns +
// Simulation::grid_bytes() / particles; resident_bytes/particle = growth of the resident set over
// construction and steps (all the step's memory; it moves with where the allocator places the
// blocks that earlier calls freed: +-100 B between runs at 1e5); allocated_bytes/particle = the
// bytes the Simulation holds allocated after the timed steps (malloc's count of bytes in use,
// not of pages: no allocator slack, the same in every run); <stage>_ns = wall time of that stage
// per particle-step from Simulation::stage_timings() (stages overlap only where the graph lets
// them: energy and time_step).
//
// BM_StepContact: the same body cut at its mid-plane z into two bodies (two particle groups,
// IField::body 0 and 1) whose halves approach at 2 m/s, so the whole cross-section is an
// interface; `single_field` and `multi_field` (solver.contact) on identical particles give the
// cost of multi-velocity-field contact (grid copies where the bodies meet, the extra mass-gradient
// scatter, the pair corrections) against the shared field.
//
// BM_StepScene/lab_impact_coarse: the step of scenes/lab-impact-coarse.toml (32 930 points;
// Tillotson, hardening, Grady-Kipp damage, uGIMP), from its start, with the same counters as
// BM_Step: the laboratory impact's memory per point, which carries the model's columns (plastic
// strain, damage, flaws) and their retake copies on top of the elastic step's.
#include <malloc.h>
#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "shatter/material/linear_elastic.hpp"
#include "shatter/mpm/simulation.hpp"
#include "shatter/scene/build.hpp"
#include "shatter/scene/scene.hpp"
#include "support/bodies.hpp"

namespace {

using namespace shatter;

constexpr double kDrift = 1000.0;  // m/s

// Resident memory of the process in bytes (/proc/self/statm), 0 where it cannot be read.
double resident_bytes() {
  std::ifstream f("/proc/self/statm");
  double pages = 0.0, resident = 0.0;
  if (!(f >> pages >> resident)) return 0.0;
  return resident * static_cast<double>(sysconf(_SC_PAGESIZE));
}

// Bytes the process holds allocated through malloc (in use, heap and mmap).
double allocated_bytes() {
  const struct mallinfo2 m = mallinfo2();
  return static_cast<double>(m.uordblks + m.hblkhd);
}

void BM_Step(benchmark::State& state, ShapeKind shape) {
  const auto threads = static_cast<int>(state.range(1));
  SolverConfig cfg;
  cfg.shape = shape;
  cfg.cell_size = bench::kCell;
  std::vector<MaterialPtr> materials{
      std::make_shared<LinearElastic>(bench::kRho, bench::kYoung, bench::kPoisson)};
  // Google Benchmark calls this function several times (to pick the iteration count), and
  // memory freed by one call is reused by the next: measure from before the first call.
  static const double rss0 = resident_bytes();
  const double allocated0 = allocated_bytes();
  Simulation sim(cfg, bench::make_body(state.range(0), kDrift), std::move(materials), threads);
  sim.step();  // warm-up: first allocation of the grid and the step-0 column re-order
  const std::vector<StageTiming> before = sim.stage_timings();
  for (auto _ : state) sim.step();
  const std::vector<StageTiming>& after = sim.stage_timings();

  const double n = static_cast<double>(sim.particles().size());
  bench::report(state, sim.particles(), sim.grid_bytes());
  // Everything the simulation holds (columns, grid, the step's scratch: stencils, displacements,
  // the copy kept for a retake), as the growth of the resident set since the first call; with
  // one benchmark per process (studies/scaling/plot_step_scaling.py) the peak footprint of the
  // step.
  state.counters["resident_bytes/particle"] = (resident_bytes() - rss0) / n;
  state.counters["allocated_bytes/particle"] = (allocated_bytes() - allocated0) / n;
  const double steps = static_cast<double>(state.iterations());
  for (std::size_t s = 0; s < after.size(); ++s) {
    const double ns = 1e9 * (after[s].seconds - before[s].seconds) / (steps * n);
    state.counters[after[s].name + "_ns"] = ns;
  }
  state.counters["blocks"] = static_cast<double>(sim.active_blocks());
}

// make_body(n) split at the mid-plane z into two groups / bodies, lower half first.
ParticleStore two_bodies(std::int64_t n) {
  const ParticleStore a = bench::make_body(n, kDrift);
  const auto z = a.col(Field::z);
  const double mid =
      0.5 * (*std::min_element(z.begin(), z.end()) + *std::max_element(z.begin(), z.end()));
  std::vector<std::size_t> half[2];
  for (std::size_t p = 0; p < a.size(); ++p) half[z[p] > mid ? 1 : 0].push_back(p);
  ParticleStore s;
  FieldSet fields;
  for (std::size_t i = 0; i < kFieldCount; ++i) {
    if (a.has(static_cast<Field>(i))) fields = fields.with(static_cast<Field>(i));
  }
  s.require(fields);
  s.require(IField::id);
  s.require(IField::body);
  for (int b = 0; b < 2; ++b) {
    const Range r = s.add_group(0, half[b].size());
    for (std::size_t k = 0; k < half[b].size(); ++k) {
      const std::size_t p = r.begin + k, q = half[b][k];
      for (std::size_t i = 0; i < kFieldCount; ++i) {
        const Field f = static_cast<Field>(i);
        if (a.has(f)) s.col(f)[p] = a.col(f)[q];
      }
      s.col(Field::vz)[p] += b == 0 ? 1.0 : -1.0;  // the halves approach
      s.col(IField::id)[p] = static_cast<std::int64_t>(q);
      s.col(IField::body)[p] = b;
    }
  }
  return s;
}

void BM_StepContact(benchmark::State& state, ContactKind contact) {
  const auto threads = static_cast<int>(state.range(1));
  SolverConfig cfg;
  cfg.cell_size = bench::kCell;
  cfg.contact.kind = contact;
  cfg.contact.friction = 0.5;
  std::vector<MaterialPtr> materials{
      std::make_shared<LinearElastic>(bench::kRho, bench::kYoung, bench::kPoisson)};
  Simulation sim(cfg, two_bodies(state.range(0)), std::move(materials), threads);
  sim.step();
  const std::vector<StageTiming> before = sim.stage_timings();
  for (auto _ : state) sim.step();
  const std::vector<StageTiming>& after = sim.stage_timings();
  const double n = static_cast<double>(sim.particles().size());
  bench::report(state, sim.particles(), sim.grid_bytes());
  const double steps = static_cast<double>(state.iterations());
  for (std::size_t s = 0; s < after.size(); ++s) {
    state.counters[after[s].name + "_ns"] =
        1e9 * (after[s].seconds - before[s].seconds) / (steps * n);
  }
  state.counters["blocks"] = static_cast<double>(sim.active_blocks());
}

void BM_StepScene(benchmark::State& state, const char* scene_file) {
  const auto threads = static_cast<int>(state.range(0));
  const double allocated0 = allocated_bytes();
  std::unique_ptr<Solver> sim;
  {
    const scene::Scene sc =
        scene::load_scene(std::string(SHATTER_SOURCE_DIR) + "/scenes/" + scene_file);
    scene::BuiltScene built = scene::build(sc);
    sim = scene::make_solver(sc, std::move(built.particles), std::move(built.materials), threads);
  }
  sim->step();
  const std::vector<StageTiming> before = sim->stage_timings();
  for (auto _ : state) sim->step();
  const std::vector<StageTiming>& after = sim->stage_timings();
  const double n = static_cast<double>(sim->particles().size());
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(sim->particles().size()));
  state.counters["allocated_bytes/particle"] = (allocated_bytes() - allocated0) / n;
  state.counters["retakes"] = static_cast<double>(sim->retakes());
  const double steps = static_cast<double>(state.iterations());
  for (std::size_t s = 0; s < after.size(); ++s) {
    state.counters[after[s].name + "_ns"] =
        1e9 * (after[s].seconds - before[s].seconds) / (steps * n);
  }
}

void steps(benchmark::internal::Benchmark* b) {
  bench::sizes_and_threads(b);
}

}  // namespace

BENCHMARK_CAPTURE(BM_Step, ugimp, ShapeKind::ugimp)->Apply(steps);
BENCHMARK_CAPTURE(BM_Step, linear, ShapeKind::linear)->Apply(steps);
BENCHMARK_CAPTURE(BM_Step, bspline2, ShapeKind::bspline2)->Apply(steps);

BENCHMARK_CAPTURE(BM_StepContact, single_field, ContactKind::single_field)->Apply(steps);
BENCHMARK_CAPTURE(BM_StepContact, multi_field, ContactKind::multi_field)->Apply(steps);

BENCHMARK_CAPTURE(BM_StepScene, lab_impact_coarse, "lab-impact-coarse.toml")
    ->ArgName("threads")
    ->Arg(1)
    ->Arg(2)
    ->MeasureProcessCPUTime()
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
