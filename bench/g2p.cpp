// G2P (App. A.2 step 5): particle velocity and displacement from the nodal acceleration and
// velocity through kernels::g2p_block (stencils stored by P2G), with the engine's per-particle
// extras (time-centred kinetic and potential energy), as the engine's g2p stage runs it.
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
      mpm::g2p_inputs(P, 1.0 / bench::kCell, dx.data(), dy.data(), dz.data());
  // Tiny steps so that repeated kicks leave the velocities where they are.
  in.dt_velocity = 1e-12;
  in.dt_position = 1e-12;
  const double half_dt_prev = 0.5e-12;
  const double* mass = P.col(Field::mass).data();
  in.stencil = body.stencils(kernels::StencilCache::kLoad);
  const double w = half_dt_prev / in.dt_velocity;
  const auto energies = [&](std::size_t p, const double(&v0)[3]) {
    const double vn[3] = {v0[0] + w * (in.vx[p] - v0[0]), v0[1] + w * (in.vy[p] - v0[1]),
                          v0[2] + w * (in.vz[p] - v0[2])};
    kinetic[p] = 0.5 * mass[p] * (vn[0] * vn[0] + vn[1] * vn[1] + vn[2] * vn[2]);
    potential[p] = 0.0;
  };
  tbb::task_arena arena(static_cast<int>(state.range(1)));
  arena.execute([&] {
    for (auto _ : state) {
      bench::gather_blocks<kernels::G2PWindow>(
          grid, [&](std::span<const std::uint32_t> run, const SparseGrid::Coord& owner,
                    const std::uint32_t* nb, kernels::G2PWindow& win) {
            kernels::g2p_block<Shape>(in, run, owner, nb, grid.nodes(), win, energies);
          });
      benchmark::ClobberMemory();
    }
  });
  bench::report(state, P, grid.bytes());
  // x, size0, mass; v (rw); d, kinetic, potential; the stored stencil (18 doubles + 1 byte)
  state.counters["col_bytes_rw"] = 8.0 * 17 + 8.0 * kernels::Stencil<Shape>::kRow + 1.0;
}

}  // namespace

BENCHMARK(BM_G2P<kernels::GimpShape>)->Name("g2p/ugimp")->Apply(bench::sizes_and_threads);

BENCHMARK_MAIN();
