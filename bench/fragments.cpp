// Fragment search throughput (MPM paper Sec. 4.1.2 and BA95 Sec. 4.4) at 1e5 and 1e6 particles,
// and the Grady–Kipp policy update (Eqs. 17–19) over SoA columns, scalar against SIMD.

#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include <xsimd/xsimd.hpp>

#include "damage/grady_kipp.hpp"
#include "shatter/core/particles.hpp"
#include "shatter/fracture/counter_rng.hpp"
#include "shatter/fracture/fragments.hpp"
#include "support/bodies.hpp"

namespace {

using namespace shatter;

// The native batch (AVX-512 on the benchmark machine), as the constitutive kernels use it, and
// the AVX2 batch for comparison.
using Batch = xsimd::batch<double>;
#if XSIMD_WITH_AVX2
using Batch4 = xsimd::batch<double, xsimd::avx2>;
#else
using Batch4 = Batch;
#endif

// A lattice ball of about n points, damaged like a shattered target: failed planes every 12
// spacings in x and y, 10% random failed points, the rest partly damaged.
ParticleStore shattered_ball(std::size_t n) {
  const double d = 1.0e-3;
  const int r = static_cast<int>(std::ceil(std::cbrt(3.0 * static_cast<double>(n) / 12.566)));
  std::vector<std::array<double, 3>> pts;
  for (int i = -r; i <= r; ++i)
    for (int j = -r; j <= r; ++j)
      for (int k = -r; k <= r; ++k)
        if (i * i + j * j + k * k <= r * r) pts.push_back({i * d, j * d, k * d});
  ParticleStore s;
  s.require(FieldSet{Field::x, Field::y, Field::z, Field::vx, Field::vy, Field::vz, Field::mass,
                     Field::volume0, Field::damage});
  s.require(IField::id);
  s.require(IField::fragment);
  s.add_group(0, pts.size());
  for (std::size_t p = 0; p < pts.size(); ++p) {
    s.col(Field::x)[p] = pts[p][0];
    s.col(Field::y)[p] = pts[p][1];
    s.col(Field::z)[p] = pts[p][2];
    s.col(Field::vx)[p] = pts[p][0] * 100.0;
    s.col(Field::mass)[p] = 2.7e-6;
    s.col(Field::volume0)[p] = d * d * d;
    const auto i = static_cast<long>(std::lround(pts[p][0] / d));
    const auto j = static_cast<long>(std::lround(pts[p][1] / d));
    const double u = counter_uniform(5, p, 0);
    s.col(Field::damage)[p] = (i % 12 == 0 || j % 12 == 0 || u < 0.1) ? 1.0 : 0.5 * u;
    s.col(IField::id)[p] = static_cast<std::int64_t>(p);
  }
  return s;
}

void fragment_search(benchmark::State& state, const char* method) {
  ParticleStore s = shattered_ball(static_cast<std::size_t>(state.range(0)));
  FragmentSearchSpec spec;
  spec.method = method;
  std::size_t fragments = 0;
  for (auto _ : state) {
    const FragmentCatalogue cat = find_fragments(s, spec);
    fragments = cat.fragments.size();
    benchmark::DoNotOptimize(cat.total_mass);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(s.size()));
  state.counters["particles"] = static_cast<double>(s.size());
  state.counters["fragments"] = static_cast<double>(fragments);
}

void BM_FragmentSearchGridDensity(benchmark::State& state) {
  fragment_search(state, "grid_density");
}
void BM_FragmentSearchFriendsOfFriends(benchmark::State& state) {
  fragment_search(state, "friends_of_friends");
}
// 1e5 and 1e6 points, or SHATTER_BENCH_PARTICLES (bench::particle_counts).
void point_counts(benchmark::internal::Benchmark* b) {
  for (const std::int64_t n : shatter::bench::particle_counts({100000, 1000000})) b->Arg(n);
  b->Unit(benchmark::kMillisecond);
}
BENCHMARK(BM_FragmentSearchGridDensity)->Apply(point_counts);
BENCHMARK(BM_FragmentSearchFriendsOfFriends)->Apply(point_counts);

// SoA columns of one material group in tension near activation, so that every branch of the
// policy (inactive, growing, capped) is exercised.
struct Columns {
  explicit Columns(std::size_t n)
      : s(6, AlignedVector<double>(n)),
        damage(n),
        eps_min(n),
        eps_max(n),
        n_flaws(n),
        weibull_m(n),
        n_active(n),
        volume(n, 1e-9),
        soundspeed(n, 5000.0) {
    for (std::size_t p = 0; p < n; ++p) {
      for (std::size_t c = 0; c < 6; ++c) s[c][p] = (counter_uniform(1, p, c) - 0.3) * 2e7;
      damage[p] = 0.5 * counter_uniform(2, p, 0);
      eps_min[p] = 1e-4 * (0.5 + counter_uniform(3, p, 0));
      n_flaws[p] = 1000.0;
      weibull_m[p] = 30.0;
      eps_max[p] = eps_min[p] * std::pow(1000.0, 1.0 / 30.0);
    }
  }
  std::vector<AlignedVector<double>> s;
  AlignedVector<double> damage, eps_min, eps_max, n_flaws, weibull_m, n_active, volume, soundspeed;
};

template <class T>
constexpr std::size_t kLanes = 1;
template <>
constexpr std::size_t kLanes<Batch> = Batch::size;
#if XSIMD_WITH_AVX2 && XSIMD_WITH_AVX512F
template <>
constexpr std::size_t kLanes<Batch4> = Batch4::size;
#endif

template <class T>
T load_lanes(const double* p) {
  if constexpr (std::is_same_v<T, double>) {
    return *p;
  } else {
    return T::load_aligned(p);
  }
}
template <class T>
void store_lanes(double* p, const T& v) {
  if constexpr (std::is_same_v<T, double>) {
    *p = v;
  } else {
    v.store_aligned(p);
  }
}

template <class T>
void grady_kipp_update(benchmark::State& state) {
  const std::size_t n = 100000;
  Columns c(n);
  const damage::GradyKipp gk{};
  constexpr std::size_t w = kLanes<T>;
  for (auto _ : state) {
    for (std::size_t p = 0; p + w <= n; p += w) {
      damage::DamageInput<T> in;
      for (std::size_t k = 0; k < 6; ++k) in.s[k] = load_lanes<T>(&c.s[k][p]);
      in.young = T(53.1e9);
      in.soundspeed = load_lanes<T>(&c.soundspeed[p]);
      in.volume = load_lanes<T>(&c.volume[p]);
      in.dplastic = T(0.0);
      in.dt = 1e-9;
      damage::DamageState<T> st{load_lanes<T>(&c.damage[p]),    load_lanes<T>(&c.eps_min[p]),
                                load_lanes<T>(&c.eps_max[p]),   load_lanes<T>(&c.n_flaws[p]),
                                load_lanes<T>(&c.weibull_m[p]), T(0.0)};
      gk.evolve(in, st);
      store_lanes(&c.damage[p], st.damage);
      store_lanes(&c.n_active[p], st.n_active);
    }
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(n));
}

void BM_GradyKippScalar(benchmark::State& state) {
  grady_kipp_update<double>(state);
}
void BM_GradyKippSimd(benchmark::State& state) {
  grady_kipp_update<Batch>(state);
}
BENCHMARK(BM_GradyKippScalar)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_GradyKippSimd)->Unit(benchmark::kMicrosecond);
#if XSIMD_WITH_AVX2 && XSIMD_WITH_AVX512F
void BM_GradyKippSimdAvx2(benchmark::State& state) {
  grady_kipp_update<Batch4>(state);
}
BENCHMARK(BM_GradyKippSimdAvx2)->Unit(benchmark::kMicrosecond);
#endif

}  // namespace

BENCHMARK_MAIN();
