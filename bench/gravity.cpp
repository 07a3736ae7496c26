// Self-gravity's mesh solve (src/gravity, issue 30): CIC deposit, the FFT convolution on the
// doubled mesh, the centred difference and the interpolation back, for the points of a body
// (bench::make_body) on the default 64-node mesh (128^3 FFT) and on 32 nodes.
#include <vector>

#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include "shatter/gravity/mesh_gravity.hpp"
#include "support/bodies.hpp"

namespace {

using namespace shatter;

void BM_MeshGravity(benchmark::State& state) {
  const ParticleStore P = bench::make_body(state.range(0));
  const std::size_t n = P.size();
  std::vector<double> ax(n), ay(n), az(n);
  const gravity::MassPoints pts{n, P.col(Field::x).data(), P.col(Field::y).data(),
                                P.col(Field::z).data(), P.col(Field::mass).data()};
  gravity::MeshGravity mesh(static_cast<int>(state.range(2)));
  tbb::task_arena arena(static_cast<int>(state.range(1)));
  arena.execute([&] {
    for (auto _ : state) {
      benchmark::DoNotOptimize(
          mesh.solve(pts, gravity::kNewtonG, {ax.data(), ay.data(), az.data(), nullptr}));
      benchmark::ClobberMemory();
    }
  });
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(n));
}

void sizes(benchmark::internal::Benchmark* b) {
  for (const std::int64_t n : bench::particle_counts({100'000, 1'000'000})) {
    for (const std::int64_t t : {1, 2}) {
      for (const std::int64_t cells : {32, 64}) b->Args({n, t, cells});
    }
  }
  b->ArgNames({"particles", "threads", "mesh"});
  b->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime();
}

BENCHMARK(BM_MeshGravity)->Name("gravity/mesh_solve")->Apply(sizes);

}  // namespace

BENCHMARK_MAIN();
