// The SPH method (issue 10): the neighbour search alone and the whole solid-SPH step,
// SphSolver::step() (kick, rates pass, material update, drift, search, forces pass, energy and
// time step), on a basalt cube of the lab-impact material: Tillotson EOS + linear-hardening
// strength + Grady-Kipp damage with explicit flaws, composed as for MPM. h = 1.2 spacings
// (56 neighbours in the bulk). The cube carries a smooth velocity field of ~10 m/s so that every
// stage has real work (strain, stress, viscosity on compression).
//
// Counters: items/s = particle-steps (or particle searches) per wall second; items/cpu_s = the
// same per second of process CPU time (all threads: the comparable figure on a shared machine);
// neighbours = mean list length (with the Verlet skin's entries); bytes/particle = registered
// particle columns + what the solver holds (SphSolver::bytes(): its arrays, the search's lists,
// cells and buffers, the per-pair viscous weights, scratch; capacities), columns_B and search_B
// two of those parts; <stage>_ns = wall time of that stage per particle-step from
// SphSolver::stage_timings().
#include <cmath>
#include <ctime>
#include <memory>
#include <string>

#include <benchmark/benchmark.h>
#include <fmt/format.h>
#include <tbb/task_arena.h>

#include "shatter/scene/build.hpp"
#include "shatter/scene/scene.hpp"
#include "shatter/sph/solver.hpp"
#include "support/bodies.hpp"

namespace {

using namespace shatter;

constexpr double kSpacing = 1.0e-3;  // m

// A cube of e^3 points (e^3 closest to n) of basalt with damage, and its smooth velocity field.
std::unique_ptr<sph::SphSolver> make_cube(std::int64_t n, int threads, double skin = 0.1) {
  const int e = static_cast<int>(std::lround(std::cbrt(static_cast<double>(n))));
  const double side = e * kSpacing;
  const std::string text = fmt::format(R"(
[solver]
method = "sph"
cell_size = {0}
end_time = 1.0
[body.cube]
shape = "box"
lo = [0.0, 0.0, 0.0]
hi = [{1}, {1}, {1}]
material = "basalt"
points_per_cell = 1
[solver.sph]
skin = {2}
[body.cube.damage]
model = "grady_kipp"
weibull_m = 8.5
weibull_k = 3.0e39
total_flaws = 1.0e9
)",
                                       kSpacing, side, skin);
  const scene::Scene s = scene::parse_scene(text, "bench.toml");
  scene::BuiltScene b = scene::build(s);
  ParticleStore& P = b.particles;
  const double k = 2.0 * M_PI / side;
  for (std::size_t p = 0; p < P.size(); ++p) {
    const double x = P.col(Field::x)[p], y = P.col(Field::y)[p], z = P.col(Field::z)[p];
    P.col(Field::vx)[p] = 10.0 * std::sin(k * y) + 5.0 * std::sin(k * x);
    P.col(Field::vy)[p] = 8.0 * std::sin(k * z);
    P.col(Field::vz)[p] = -6.0 * std::sin(k * x);
  }
  return std::make_unique<sph::SphSolver>(s.solver, s.sph, std::move(b.particles), b.materials,
                                          threads);
}

// Process CPU time (all threads), seconds.
double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

void BM_NeighbourSearch(benchmark::State& state) {
  const auto threads = static_cast<int>(state.range(1));
  auto sim = make_cube(state.range(0), threads);
  const auto h = sim->smoothing_length();
  const ParticleStore& P = sim->particles();
  sph::NeighbourSearch search;
  tbb::task_arena arena(threads);
  arena.execute([&] {
    search.build(P.col(Field::x).data(), P.col(Field::y).data(), P.col(Field::z).data(), h.data(),
                 P.size());  // warm-up: first allocation
    const double c0 = cpu_seconds();
    for (auto _ : state) {
      search.build(P.col(Field::x).data(), P.col(Field::y).data(), P.col(Field::z).data(), h.data(),
                   P.size());
    }
    state.counters["items/cpu_s"] = static_cast<double>(state.iterations()) *
                                    static_cast<double>(P.size()) / (cpu_seconds() - c0);
  });
  const double n = static_cast<double>(P.size());
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(P.size()));
  state.counters["neighbours"] = static_cast<double>(search.pairs()) / n;
  state.counters["bytes/particle"] = static_cast<double>(search.bytes()) / n;
}

void BM_SphStep(benchmark::State& state) {
  auto sim = make_cube(state.range(0), static_cast<int>(state.range(1)),
                       static_cast<double>(state.range(2)) / 100.0);
  sim->step();  // warm-up
  const std::vector<StageTiming> before = sim->stage_timings();
  const std::uint64_t builds0 = sim->neighbour_builds();
  const double c0 = cpu_seconds();
  for (auto _ : state) sim->step();
  const double cpu = cpu_seconds() - c0;
  const std::vector<StageTiming>& after = sim->stage_timings();
  const double n = static_cast<double>(sim->particles().size());
  bench::report(state, sim->particles(), sim->bytes());
  // The parts of bytes/particle: the store's columns, the search (lists, cells, sort buffers).
  state.counters["columns_B"] = bench::column_bytes_per_particle(sim->particles());
  state.counters["search_B"] = static_cast<double>(sim->neighbours().bytes()) / n;
  const double steps = static_cast<double>(state.iterations());
  for (std::size_t s = 0; s < after.size(); ++s) {
    state.counters[after[s].name + "_ns"] =
        1e9 * (after[s].seconds - before[s].seconds) / (steps * n);
  }
  state.counters["items/cpu_s"] = steps * n / cpu;
  state.counters["neighbours"] = static_cast<double>(sim->neighbours().pairs()) / n;
  state.counters["builds/step"] = static_cast<double>(sim->neighbour_builds() - builds0) / steps;
}

// particles {1e5, 1e6} x threads {1, 2} x Verlet skin {0, 10 %} of 2 max h (0: lists rebuilt
// every step, as before the skin; 10 %: the default).
void sizes_threads_skins(benchmark::internal::Benchmark* b) {
  b->ArgNames({"particles", "threads", "skin%"});
  for (const std::int64_t n : {100'000, 1'000'000}) {
    for (const std::int64_t t : {1, 2}) {
      for (const std::int64_t skin : {0, 10}) b->Args({n, t, skin});
    }
  }
  b->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime();
}

}  // namespace

BENCHMARK(BM_NeighbourSearch)->Apply(bench::sizes_and_threads);
BENCHMARK(BM_SphStep)->Apply(sizes_threads_skins);

BENCHMARK_MAIN();
