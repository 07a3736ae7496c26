// The elastic constitutive part of the step (App. A.2 step 7): the velocity-gradient stage
// (kernels::velocity_gradient_block: strain and spin increments, density) and the engine's
// linear elastic model (LinearElastic::update: Jaumann rotation, Hooke increment, energy,
// pressure, sound speed), each alone.
#include <memory>

#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include "shatter/material/linear_elastic.hpp"
#include "support/stages.hpp"

namespace {

using namespace shatter;

template <class Shape>
void BM_VelocityGradient(benchmark::State& state) {
  bench::Prepared<Shape> body(state.range(0));
  ParticleStore& P = body.store;
  P.require(kStrainIncrement | kSpinIncrement);
  const SparseGrid& grid = body.grid;
  // dt = 1e-12: repeated density updates stay at rho0.
  kernels::GradientParticles in = mpm::gradient_inputs(P, 1.0 / bench::kCell, 1e-12);
  in.stencil = body.stencils(kernels::StencilCache::kLoad);
  tbb::task_arena arena(static_cast<int>(state.range(1)));
  arena.execute([&] {
    for (auto _ : state) {
      bench::gather_blocks<kernels::GradientWindow>(
          grid, [&](std::span<const std::uint32_t> run, const SparseGrid::Coord& owner,
                    const std::uint32_t* nb, kernels::GradientWindow& win) {
            kernels::velocity_gradient_block<Shape>(in, run, owner, nb, grid.nodes(), win);
          });
      benchmark::ClobberMemory();
    }
  });
  bench::report(state, P, grid.bytes());
  // x, size0, rho (rw), 9 increments; the stored stencil (18 doubles + 1 byte)
  state.counters["col_bytes_rw"] = 8.0 * 14 + 8.0 * kernels::Stencil<Shape>::kRow + 1.0;
}

void BM_ElasticUpdate(benchmark::State& state) {
  ParticleStore P = bench::make_body(state.range(0));
  P.require(kStrainIncrement | kSpinIncrement);
  const LinearElastic model(bench::kRho, bench::kYoung, bench::kPoisson);
  model.initialise(P, P.groups()[0].range);
  // Small, non-zero strain and spin increments.
  for (std::size_t p = 0; p < P.size(); ++p) {
    const double s = 1e-12 * static_cast<double>(p % 7);
    P.col(Field::deps_xx)[p] = s;
    P.col(Field::deps_yy)[p] = -0.5 * s;
    P.col(Field::deps_xy)[p] = 0.3 * s;
    P.col(Field::dspin_xy)[p] = 0.2 * s;
    P.col(Field::dspin_xz)[p] = -0.1 * s;
  }
  const ConstitutiveContext ctx{1e-7, bench::kCell, {}};
  tbb::task_arena arena(static_cast<int>(state.range(1)));
  arena.execute([&] {
    for (auto _ : state) {
      for (const Group& g : P.groups()) model.update(P, g.range, ctx);
      benchmark::ClobberMemory();
    }
  });
  bench::report(state, P, 0);
  // stress (rw), 6 strain + 3 spin increments, rho, energy (rw), pressure, sound speed
  state.counters["col_bytes_rw"] = 8.0 * 20;
}

}  // namespace

BENCHMARK(BM_VelocityGradient<kernels::GimpShape>)
    ->Name("velocity_gradient/ugimp")
    ->Apply(bench::sizes_and_threads);
BENCHMARK(BM_ElasticUpdate)->Name("elastic_update")->Apply(bench::sizes_and_threads);

BENCHMARK_MAIN();
