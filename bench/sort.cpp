// Sort-by-cell (App. A.2 step 1 of the stage graph), in its three parts as the engine's sort
// stage runs them:
//  keys    - owner-block key of every particle (parallel), every step;
//  assign  - SparseGrid::assign: blocks, neighbours, colours and per-block particle lists,
//            rebuilt every step in which any particle changed owner block (serial);
//  reorder - stable sort of the particle order by key and ParticleStore::permute of every
//            registered column, every reorder_interval (25) steps (serial); measured in the
//            steady state, on a store that is already block-sorted;
//  stencils - kernels::store_stencils: each particle's weights, gradients and node offsets,
//            stored for the four transfers of the step (parallel), every step.
#include <numeric>
#include <vector>

#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include "support/stages.hpp"

namespace {

using namespace shatter;
using Shape = kernels::GimpShape;

void BM_Keys(benchmark::State& state) {
  ParticleStore P = bench::make_body(state.range(0));
  bench::sort_by_block<Shape>(P);
  std::vector<std::uint64_t> keys;
  tbb::task_arena arena(static_cast<int>(state.range(1)));
  arena.execute([&] {
    for (auto _ : state) {
      bench::owner_keys<Shape>(P, keys);
      benchmark::ClobberMemory();
    }
  });
  bench::report(state, P, 0);
}

void BM_Assign(benchmark::State& state) {
  ParticleStore P = bench::make_body(state.range(0));
  const auto keys = bench::sort_by_block<Shape>(P);
  // The same body one block further along x: every key differs, so every assign rebuilds.
  std::vector<std::uint64_t> shifted(keys.size());
  for (std::size_t p = 0; p < keys.size(); ++p) shifted[p] = keys[p] + (std::uint64_t{1} << 42);
  SparseGrid grid;
  bool flip = false;
  tbb::task_arena arena(static_cast<int>(state.range(1)));
  arena.execute([&] {
    for (auto _ : state) {
      benchmark::DoNotOptimize(grid.assign(flip ? shifted : keys));
      flip = !flip;
    }
  });
  bench::report(state, P, grid.bytes());
  state.counters["blocks"] = static_cast<double>(grid.blocks());
}

void BM_Reorder(benchmark::State& state) {
  ParticleStore P = bench::make_body(state.range(0));
  bench::sort_by_block<Shape>(P);
  std::vector<std::uint64_t> keys;
  bench::owner_keys<Shape>(P, keys);
  std::vector<std::uint32_t> order(P.size());
  std::vector<std::uint64_t> sorted(P.size());
  tbb::task_arena arena(static_cast<int>(state.range(1)));
  arena.execute([&] {
    for (auto _ : state) {
      std::iota(order.begin(), order.end(), 0U);
      std::stable_sort(order.begin(), order.end(),
                       [&](std::uint32_t a, std::uint32_t b) { return keys[a] < keys[b]; });
      P.permute(order);
      for (std::size_t k = 0; k < P.size(); ++k) sorted[k] = keys[order[k]];
      benchmark::ClobberMemory();
    }
  });
  bench::report(state, P, 0);
  state.counters["columns"] = bench::column_bytes_per_particle(P) / 8.0;
}

void BM_Stencils(benchmark::State& state) {
  ParticleStore P = bench::make_body(state.range(0));
  bench::sort_by_block<Shape>(P);
  AlignedVector<double> w(P.size() * kernels::Stencil<Shape>::kRow);
  std::vector<std::uint8_t> off(P.size());
  const kernels::StencilCache cache{w.data(), off.data(), kernels::StencilCache::kStore};
  const double* X[3] = {P.col(Field::x).data(), P.col(Field::y).data(), P.col(Field::z).data()};
  const double* size0 = P.col(Field::size0).data();
  tbb::task_arena arena(static_cast<int>(state.range(1)));
  arena.execute([&] {
    for (auto _ : state) {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, P.size(), bench::kParticleGrain),
                        [&](const tbb::blocked_range<std::size_t>& r) {
                          kernels::store_stencils<Shape>(X, size0, 1.0 / bench::kCell, r.begin(),
                                                         r.end(), cache);
                        });
      benchmark::ClobberMemory();
    }
  });
  bench::report(state, P, 0);
  state.counters["stencil_bytes"] = 8.0 * kernels::Stencil<Shape>::kRow + 1.0;
}

}  // namespace

BENCHMARK(BM_Keys)->Name("sort/keys")->Apply(shatter::bench::sizes_and_threads);
BENCHMARK(BM_Assign)->Name("sort/assign")->Apply(shatter::bench::sizes_and_threads);
BENCHMARK(BM_Reorder)->Name("sort/reorder")->Apply(shatter::bench::sizes_and_threads);
BENCHMARK(BM_Stencils)->Name("sort/stencils")->Apply(shatter::bench::sizes_and_threads);

BENCHMARK_MAIN();
