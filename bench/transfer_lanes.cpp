// The gathers' arithmetic core with its lanes laid two ways (issue 35, "8 particles per vector";
// docs/performance.md, "MPM transfers, round 4"): the engine's lanes over ONE particle's
// components (kernels::g2p_gather, kernels::velocity_gradient_gather) against 8 particles per
// vector, each lane one particle, the node values fetched with AVX-512 gathers (vgatherdpd) from
// the same G2P window. Both read stencils stored as the engine stores them
// (kernels::StencilCache rows, kLoad) and one block's window, so the figures isolate the core
// of the stage: no particle columns, no window loads. particles:32768 keeps the stencil rows in
// L2/L3, particles:1000000 streams them from DRAM (145 B per particle, as the engine's four
// transfers do). The 8-lane G2P is checked bit for bit against the engine's kernel before it is
// timed (each lane does the scalar loop's operations in its order), and fails the benchmark
// otherwise. in_place: the same engine kernels reading each stored row where it lies
// (kernels::StoredStencil, as the engine's stages now do) instead of a copy into a
// kernels::Stencil (Stencil::prepare, as before), checked bit for bit against the copy.
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "mpm/g2p.hpp"
#include "mpm/velocity_gradient.hpp"
#include "support/bodies.hpp"

namespace {

using namespace shatter;
using Shape = kernels::GimpShape;
constexpr int W = Shape::kWidth;
using Row = kernels::Stencil<Shape>;

// n uGIMP stencils of particles spread over one owner block (block (1, 1, 1): first nodes 4..7,
// offsets 0..3 on each axis), stored as the engine's sort stage stores them; and a window of
// node values.
struct Setup {
  std::vector<double> w;
  std::vector<std::uint8_t> off;
  kernels::G2PWindow g2p{};
  kernels::GradientWindow grad{};
  SparseGrid::Coord owner{1, 1, 1};
  std::size_t n;

  explicit Setup(std::size_t count) : w(count * Row::kRow), off(count), n(count) {
    std::mt19937_64 rng(35);
    std::uniform_real_distribution<double> in_block(4.5, 8.499), value(-1.0, 1.0);
    std::vector<double> x[3];
    for (auto& c : x) c.resize(n);
    for (std::size_t p = 0; p < n; ++p) {
      for (auto& c : x) c[p] = in_block(rng);
    }
    const std::vector<double> size0(n, 0.5);  // half-width 1/4 cell
    const double* const X[3] = {x[0].data(), x[1].data(), x[2].data()};
    kernels::store_stencils<Shape>(X, size0.data(), 1.0, 0, n,
                                   {w.data(), off.data(), kernels::StencilCache::kStore});
    for (int i = 0; i < kernels::WindowGeometry::kSize; ++i) {
      double* node = g2p.fp(i);
      for (int f = 0; f < 6; ++f) node[f] = value(rng);
      node[6] = node[7] = 0.0;
      for (int f = 0; f < 3; ++f) grad.v[f][i] = node[3 + f];
    }
  }
  kernels::StencilCache cache() { return {w.data(), off.data(), kernels::StencilCache::kLoad}; }
};

// The engine's G2P core, particle by particle: the 6 sums (acceleration, velocity) of each,
// the stencil copied (Stencil::prepare) or read in place (StoredStencil).
template <bool kInPlace>
void g2p_particle_lanes(Setup& s, std::vector<double>& out) {
  const kernels::StencilCache cache = s.cache();
  Row st;
  const double xi[3] = {};
  for (std::size_t p = 0; p < s.n; ++p) {
    alignas(64) double sum[8];
    alignas(32) double unused[4];
    if constexpr (kInPlace) {
      kernels::g2p_gather<false>(kernels::StoredStencil<Shape>(cache, p), s.g2p, sum, unused);
    } else {
      st.prepare(cache, p, xi, 1.0, 0.0, s.owner);
      kernels::g2p_gather<false>(st, s.g2p, sum, unused);
    }
    std::memcpy(&out[6 * p], sum, 6 * sizeof(double));
  }
}

// The engine's velocity-gradient core (4-wide lanes over the gradient's components), the
// stencil copied or read in place.
template <bool kInPlace>
void gradient_particle_lanes(Setup& s, std::vector<double>& out) {
  const kernels::StencilCache cache = s.cache();
  Row st;
  const double xi[3] = {};
  for (std::size_t p = 0; p < s.n; ++p) {
    alignas(32) double L[3][4];
    if constexpr (kInPlace) {
      kernels::velocity_gradient_gather(kernels::StoredStencil<Shape>(cache, p), s.grad, L);
    } else {
      st.prepare(cache, p, xi, 1.0, 0.0, s.owner);
      kernels::velocity_gradient_gather(st, s.grad, L);
    }
    std::memcpy(&out[12 * p], L, sizeof L);
  }
}

// Times kernel(s, out) over the particles after checking its output bit for bit against
// reference(s, out) (none: no check).
template <class Kernel, class Reference>
void run(benchmark::State& state, std::size_t n, std::size_t per, Kernel&& kernel,
         Reference&& reference) {
  Setup s(n);
  std::vector<double> out(per * s.n), expected(per * s.n);
  reference(s, expected);
  kernel(s, out);
  if (std::memcmp(out.data(), expected.data(), out.size() * sizeof(double)) != 0) {
    state.SkipWithError("not bitwise equal to the engine's kernel with a copied stencil");
    return;
  }
  for (auto _ : state) {
    kernel(s, out);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(s.n));
}

#if defined(__AVX512F__)
// 8 particles per vector: lane k sums particle p + k's stencil. The weights come from the 8
// stored rows (transposed here, as a stage would have to), the node values by one gather per
// field and node from the window (node (a, b, c) of lane k at its own window index).
void g2p_particles_in_lanes(Setup& s, std::vector<double>& out) {
  for (std::size_t p = 0; p + 8 <= s.n; p += 8) {
    alignas(64) double w[3][W][8];
    alignas(32) std::int32_t first[8];
    for (int k = 0; k < 8; ++k) {
      const double* row = &s.w[(p + k) * Row::kRow];
      for (int d = 0; d < 3; ++d) {
        for (int a = 0; a < W; ++a) w[d][a][k] = row[d * W + a];
      }
      const unsigned o = s.off[p + k];
      const int ox = o & 3U, oy = (o >> 2) & 3U, oz = (o >> 4) & 3U;
      first[k] =
          8 * ((ox * kernels::WindowGeometry::kEdge + oy) * kernels::WindowGeometry::kEdge + oz);
    }
    const __m256i base = _mm256_load_si256(reinterpret_cast<const __m256i*>(first));
    __m512d sum[6];
    for (auto& v : sum) v = _mm512_setzero_pd();
    const double* fp = s.g2p.fp(0);
    constexpr int E = kernels::WindowGeometry::kEdge;
    for (int a = 0; a < W; ++a) {
      for (int b = 0; b < W; ++b) {
        const __m512d wab = _mm512_mul_pd(_mm512_load_pd(w[0][a]), _mm512_load_pd(w[1][b]));
        for (int c = 0; c < W; ++c) {
          const __m256i at = _mm256_add_epi32(base, _mm256_set1_epi32(8 * ((a * E + b) * E + c)));
          const __m512d N = _mm512_mul_pd(wab, _mm512_load_pd(w[2][c]));
          for (int f = 0; f < 6; ++f) {
            // the masked form: GCC 12 warns that the plain one reads an undefined source
            const __m512d u = _mm512_mask_i32gather_pd(_mm512_setzero_pd(), 0xFF, at, fp + f, 8);
            sum[f] = _mm512_fmadd_pd(N, u, sum[f]);
          }
        }
      }
    }
    alignas(64) double t[6][8];
    for (int f = 0; f < 6; ++f) _mm512_store_pd(t[f], sum[f]);
    for (int k = 0; k < 8; ++k) {
      for (int f = 0; f < 6; ++f) out[6 * (p + k) + f] = t[f][k];
    }
  }
}
#endif

std::size_t count(const benchmark::State& state) {
  return static_cast<std::size_t>(state.range(0)) / 8 * 8;
}

void BM_G2PParticleLanes(benchmark::State& state) {
  run(state, count(state), 6, g2p_particle_lanes<false>, g2p_particle_lanes<false>);
}
void BM_G2PParticleLanesInPlace(benchmark::State& state) {
  run(state, count(state), 6, g2p_particle_lanes<true>, g2p_particle_lanes<false>);
}
#if defined(__AVX512F__)
void BM_G2PParticlesInLanes(benchmark::State& state) {
  run(state, count(state), 6, g2p_particles_in_lanes, g2p_particle_lanes<false>);
}
#endif
void BM_GradientParticleLanes(benchmark::State& state) {
  run(state, count(state), 12, gradient_particle_lanes<false>, gradient_particle_lanes<false>);
}
void BM_GradientParticleLanesInPlace(benchmark::State& state) {
  run(state, count(state), 12, gradient_particle_lanes<true>, gradient_particle_lanes<false>);
}

void sizes(benchmark::internal::Benchmark* b) {
  b->ArgNames({"particles"});
  for (const std::int64_t n : bench::particle_counts({32'768, 1'000'000})) b->Arg(n);
  b->MeasureProcessCPUTime()->Unit(benchmark::kMicrosecond);
}

}  // namespace

BENCHMARK(BM_G2PParticleLanes)->Name("gather/g2p/particle_lanes")->Apply(sizes);
BENCHMARK(BM_G2PParticleLanesInPlace)->Name("gather/g2p/particle_lanes/in_place")->Apply(sizes);
#if defined(__AVX512F__)
BENCHMARK(BM_G2PParticlesInLanes)->Name("gather/g2p/particles_in_lanes")->Apply(sizes);
#endif
BENCHMARK(BM_GradientParticleLanes)->Name("gather/velocity_gradient/particle_lanes")->Apply(sizes);
BENCHMARK(BM_GradientParticleLanesInPlace)
    ->Name("gather/velocity_gradient/particle_lanes/in_place")
    ->Apply(sizes);

BENCHMARK_MAIN();
