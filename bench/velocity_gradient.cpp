// Velocity gradient (App. A.2 step 7) through kernels::velocity_gradient_block on the engine's
// uGIMP path (rows recomputed at every read, StencilCache::kRecompute): one particle at a time
// (range 2 = 0) or with the particles that share a stencil in the lanes of one vector (1:
// kernels/mpm/shared.hpp; the same bits), both in one process. The increments go to buffers of
// their own, as the engine's chunk buffers; the density is divided in place (tiny dt: it stays).
#include <vector>

#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include "support/stages.hpp"

namespace {

using namespace shatter;

void BM_VelocityGradient(benchmark::State& state) {
  using Shape = kernels::GimpShape;
  bench::Prepared<Shape> body(state.range(0));
  ParticleStore& P = body.store;
  const SparseGrid& grid = body.grid;
  const std::size_t n = P.size();
  const double ih = 1.0 / bench::kCell;
  std::vector<AlignedVector<double>> inc(9, AlignedVector<double>(n));
  kernels::GradientParticles in = mpm::gradient_inputs(P, ih, 1e-12);
  double** const out[9] = {&in.exx, &in.eyy, &in.ezz, &in.exy, &in.eyz,
                           &in.exz, &in.wxy, &in.wyz, &in.wxz};
  for (int k = 0; k < 9; ++k) *out[k] = inc[k].data();
  in.stencil.mode = kernels::StencilCache::kRecompute;
  in.stencil.x[0] = P.col(Field::x).data();
  in.stencil.x[1] = P.col(Field::y).data();
  in.stencil.x[2] = P.col(Field::z).data();
  in.stencil.size0 = P.col(Field::size0).data();
  in.stencil.inv_h = ih;
  in.stencil.shared_lanes = state.range(2) != 0;
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
}

}  // namespace

BENCHMARK(BM_VelocityGradient)
    ->Name("velocity_gradient/ugimp_recomputed")
    ->ArgsProduct({bench::particle_counts({100000, 1000000}), {1}, {0, 1}})
    ->ArgNames({"particles", "threads", "shared"});

BENCHMARK_MAIN();
