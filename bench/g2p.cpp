// G2P (App. A.2 step 5): particle velocity and displacement from the nodal acceleration and
// velocity through kernels::g2p_particle, with the engine's per-particle extras (time-centred
// kinetic and potential energy), as the engine's g2p stage runs it.
#include <vector>

#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include "support/stages.hpp"

namespace {

using namespace shatter;

template <class Shape>
void BM_G2P(benchmark::State& state) {
  bench::Prepared<Shape> body(state.range(0));
  ParticleStore& P = body.store;
  const SparseGrid& grid = body.grid;
  const std::size_t n = P.size();
  AlignedVector<double> dx(n), dy(n), dz(n), kinetic(n), potential(n);
  kernels::G2PParticles in =
      engine::g2p_inputs(P, 1.0 / bench::kCell, dx.data(), dy.data(), dz.data());
  // Tiny steps so that repeated kicks leave the velocities where they are.
  in.dt_velocity = 1e-12;
  in.dt_position = 1e-12;
  const double half_dt_prev = 0.5e-12;
  const double* mass = P.col(Field::mass).data();
  tbb::task_arena arena(static_cast<int>(state.range(1)));
  arena.execute([&] {
    for (auto _ : state) {
      tbb::parallel_for(
          tbb::blocked_range<std::size_t>(0, n, bench::kParticleGrain),
          [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t p = r.begin(); p < r.end(); ++p) {
              const double v0[3] = {in.vx[p], in.vy[p], in.vz[p]};
              const std::uint32_t b = grid.owner_of(p);
              kernels::g2p_particle<Shape>(in, p, grid.coord(b), grid.neighbours(b), grid.nodes());
              const double w = half_dt_prev / in.dt_velocity;
              const double vn[3] = {v0[0] + w * (in.vx[p] - v0[0]), v0[1] + w * (in.vy[p] - v0[1]),
                                    v0[2] + w * (in.vz[p] - v0[2])};
              kinetic[p] = 0.5 * mass[p] * (vn[0] * vn[0] + vn[1] * vn[1] + vn[2] * vn[2]);
              potential[p] = 0.0;
            }
          });
      benchmark::ClobberMemory();
    }
  });
  bench::report(state, P, grid.bytes());
  state.counters["col_bytes_rw"] = 8.0 * 17;  // x, size0, mass; v (rw); d, kinetic, potential
}

}  // namespace

BENCHMARK(BM_G2P<kernels::GimpShape>)->Name("g2p/ugimp")->Apply(bench::sizes_and_threads);

BENCHMARK_MAIN();
