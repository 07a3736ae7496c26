// The machine's two ceilings for the roofline of docs/performance.md ("Roofline"): the memory
// bandwidth a streaming kernel attains (STREAM's triad, a = b + s c, McCalpin 1995) at sizes held
// in L1, L2, L3 and DRAM, and the fp64 rate of independent fused multiply-adds in the widest
// vector the build targets (xsimd's default architecture, -march=native). A stage's attained
// bytes and flops per second are read against these, measured on the same machine in the same
// session, rather than against a data-sheet peak this virtual machine may not deliver. Rates are
// per second of process CPU time (per core busy), as the stage figures they are compared with,
// so that a machine shared with other work still gives the per-core ceilings.
// GCC 12's false -Wmaybe-uninitialized inside the AVX-512 square root (PR 105593), as in
// bench/constitutive.cpp: silenced before the intrinsic headers are included.
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ < 13
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include <benchmark/benchmark.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>
#include <xsimd/xsimd.hpp>

namespace {

// Triad over n doubles per array on `threads` threads, each thread on its own contiguous part
// (static partition, first-touched by the same thread, so that DRAM pages sit on its node).
void BM_Triad(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  std::vector<double> a(n), b(n), c(n);
  tbb::task_arena arena(threads);
  const tbb::static_partitioner part;
  arena.execute([&] {
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, n),
        [&](const tbb::blocked_range<std::size_t>& r) {
          for (std::size_t i = r.begin(); i < r.end(); ++i) {
            a[i] = 0.0;
            b[i] = 1.0 + 1e-9 * static_cast<double>(i);
            c[i] = 2.0 - 1e-9 * static_cast<double>(i);
          }
        },
        part);
  });
  const double s = 0.5;
  arena.execute([&] {
    for (auto _ : state) {
      tbb::parallel_for(
          tbb::blocked_range<std::size_t>(0, n),
          [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i < r.end(); ++i) a[i] = b[i] + s * c[i];
          },
          part);
      benchmark::DoNotOptimize(a.data());
      benchmark::ClobberMemory();
    }
  });
  // STREAM's count: two arrays read, one written (the write-allocate read is not counted).
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(24 * n));
}

// Independent FMA chains, enough of them to cover the FMA latency times the number of FMA
// pipes; each FMA is two flops per lane.
template <int kChains, class Arch = xsimd::default_arch>
void fma_chains(std::int64_t rounds, double* out) {
  using B = xsimd::batch<double, Arch>;
  B acc[kChains];
  for (int k = 0; k < kChains; ++k) acc[k] = B(1.0 + 1e-3 * k);
  const B m(0.999999), d(1e-7);
  for (std::int64_t r = 0; r < rounds; ++r) {
    for (int k = 0; k < kChains; ++k) acc[k] = xsimd::fma(acc[k], m, d);
  }
  // Summed through memory: GCC 12 flags the AVX-512 horizontal sum's intrinsic as reading an
  // uninitialised register (the same false report as in SHATTER_SANITIZE builds).
  double sum = 0.0;
  for (int k = 0; k < kChains; ++k) {
    alignas(64) double lanes[B::size];
    acc[k].store_aligned(lanes);
    for (const double x : lanes) sum += x;
  }
  *out = sum;
}

void BM_FmaPeak(benchmark::State& state) {
  constexpr int kChains = 12;
  constexpr std::int64_t kRounds = 1 << 16;
  const int threads = static_cast<int>(state.range(0));
  std::vector<double> out(static_cast<std::size_t>(threads) * 8);
  tbb::task_arena arena(threads);
  arena.execute([&] {
    for (auto _ : state) {
      tbb::parallel_for(
          0, threads, [&](int t) { fma_chains<kChains>(kRounds, &out[8 * t]); },
          tbb::static_partitioner());
      benchmark::DoNotOptimize(out.data());
    }
  });
  const double flops = 2.0 * xsimd::batch<double>::size * kChains * kRounds * threads;
  state.counters["flops"] = benchmark::Counter(flops * static_cast<double>(state.iterations()),
                                               benchmark::Counter::kIsRate);
  state.counters["lanes"] = static_cast<double>(xsimd::batch<double>::size);
}

// One thread, kChains independent chains: with one chain each FMA waits for the last (the FMA
// latency), the ceiling of a gather that sums into one accumulator (G2P's 8 lanes, the velocity
// gradient's three rows) unless the core overlaps the chains of successive points.
template <int kChains>
void BM_FmaChains(benchmark::State& state) {
  constexpr std::int64_t kRounds = 1 << 16;
  double out[8];
  for (auto _ : state) {
    fma_chains<kChains>(kRounds, out);
    benchmark::DoNotOptimize(out);
  }
  const double flops = 2.0 * xsimd::batch<double>::size * kChains * kRounds;
  state.counters["flops"] = benchmark::Counter(flops * static_cast<double>(state.iterations()),
                                               benchmark::Counter::kIsRate);
}

// Divisions and square roots of the widest vector, kChains independent chains (one thread): the
// divider is not pipelined like the FMA units, so a stage with d divisions and square roots per
// point needs at least d over this rate, whatever its FMA count (the uGIMP rows: 9-18 divisions
// per point and transfer; the SPH pair passes: a square root and 1-2 divisions per pair). Counted
// per lane: `ops` is lane-divisions (or lane-roots) per second of process CPU.
template <bool kSqrt>
void BM_Divider(benchmark::State& state) {
  using B = xsimd::batch<double>;
  constexpr int kChains = 12;
  constexpr std::int64_t kRounds = 1 << 14;
  B acc[kChains];
  for (int k = 0; k < kChains; ++k) acc[k] = B(1.5 + 1e-3 * k);
  const B m(2.0);
  for (auto _ : state) {
    for (std::int64_t r = 0; r < kRounds; ++r) {
      // x -> 2 / x returns to x every second round; sqrt converges to 1: no overflow, no denormal.
      for (int k = 0; k < kChains; ++k) acc[k] = kSqrt ? xsimd::sqrt(acc[k]) : m / acc[k];
    }
    benchmark::DoNotOptimize(acc);
  }
  const double ops = static_cast<double>(B::size) * kChains * kRounds;
  state.counters["ops"] = benchmark::Counter(ops * static_cast<double>(state.iterations()),
                                             benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Divider<false>)->Name("machine/divide")->MeasureProcessCPUTime();
BENCHMARK(BM_Divider<true>)->Name("machine/sqrt")->MeasureProcessCPUTime();

#if defined(__AVX512F__) && defined(__FMA__)
// The FMA peak in 4-lane (256-bit) vectors on an AVX-512 build: whether this core reaches its peak
// with the width of the transfers' Lanes<4> (kernels/mpm/lanes.hpp) as with 8 lanes (Zen 4 runs a
// 512-bit FMA on two 256-bit halves; a core with full-width 512-bit units would not).
void BM_FmaPeak256(benchmark::State& state) {
  using A = xsimd::fma3<xsimd::avx2>;
  constexpr std::int64_t kRounds = 1 << 16;
  double out[8];
  for (auto _ : state) {
    fma_chains<12, A>(kRounds, out);
    benchmark::DoNotOptimize(out);
  }
  const double flops = 2.0 * xsimd::batch<double, A>::size * 12 * kRounds;
  state.counters["flops"] = benchmark::Counter(flops * static_cast<double>(state.iterations()),
                                               benchmark::Counter::kIsRate);
}
BENCHMARK(BM_FmaPeak256)->Name("machine/fma_256bit")->MeasureProcessCPUTime();
#endif

// Sizes per array (three arrays each): 8 KiB (L1: 24 KiB of this machine's 32 KiB per core),
// 256 KiB (L2: 768 KiB of 1 MiB per core), 2 MiB (L3: 6 MiB of 32 MiB shared), 8 MiB (24 MiB: the
// size of the columns a stage streams at 1e5 points, near the L3's capacity), 256 MiB (DRAM); the
// smoke run (SHATTER_BENCH_PARTICLES set, bench/CMakeLists.txt) keeps the first.
void triad_sizes(benchmark::internal::Benchmark* b) {
  const bool smoke = std::getenv("SHATTER_BENCH_PARTICLES") != nullptr;
  for (const std::int64_t kib : {8, 256, 2 * 1024, 8 * 1024, 256 * 1024}) {
    for (const int threads : {1, 2}) b->Args({kib * 1024 / 8, threads});
    if (smoke) break;
  }
}

}  // namespace

BENCHMARK(BM_Triad)
    ->Name("machine/triad")
    ->ArgNames({"doubles", "threads"})
    ->Apply(triad_sizes)
    ->MeasureProcessCPUTime();
BENCHMARK(BM_FmaPeak)
    ->Name("machine/fma")
    ->ArgName("threads")
    ->Arg(1)
    ->Arg(2)
    ->MeasureProcessCPUTime();
BENCHMARK(BM_FmaChains<1>)->Name("machine/fma_chains/1")->MeasureProcessCPUTime();
BENCHMARK(BM_FmaChains<3>)->Name("machine/fma_chains/3")->MeasureProcessCPUTime();

BENCHMARK_MAIN();
