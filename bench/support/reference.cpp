// The reference kernel linked into every benchmark program (bench/CMakeLists.txt), so that each
// program measures the machine's speed of the moment beside its own figures: tools/bench_compare.py
// divides every figure by this one from the same process, and the noise of a shared machine
// (other processes, frequency, cache contention) cancels in the ratio.
//
// What it does: the mix of the transfer kernels in small, fixed and independent of the code under
// test: per element a branchy piecewise quadratic (like the uGIMP weights), a short dependent
// chain of fp64 multiply-adds, and a stream through an array larger than L2 (8 MiB, in L3).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <benchmark/benchmark.h>

namespace {

void BM_Reference(benchmark::State& state) {
  constexpr std::size_t kN = std::size_t{1} << 20;  // 8 MiB of doubles
  std::vector<double> x(kN), y(kN);
  for (std::size_t i = 0; i < kN; ++i) {
    x[i] = std::fmod(0.618033988749895 * static_cast<double>(i), 2.0) - 1.0;
    y[i] = 0.0;
  }
  for (auto _ : state) {
    double acc = 0.0;
    for (std::size_t i = 0; i < kN; ++i) {
      const double d = x[i];
      const double ad = std::abs(d);
      double w;
      if (ad <= 0.25) {
        w = 1.0 - (d * d + 0.0625) * 2.0;
      } else if (ad <= 0.75) {
        w = 1.0 - ad;
      } else {
        const double r = 1.25 - ad;
        w = r * r;
      }
      y[i] += w * d;
      acc = acc * 0.5 + w;
    }
    benchmark::DoNotOptimize(acc);
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(kN));
}

}  // namespace

BENCHMARK(BM_Reference)->Name("reference")->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();
