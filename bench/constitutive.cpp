// Constitutive update throughput (App. A.2 step 7) per model combination, scalar reference path
// against the xsimd path: particles per second (items_per_second) for 1e5 and 1e6 particles.

// GCC 12 false positive inside AVX-512 intrinsics (PR 105593), see constitutive/simd.hpp; it
// must be silenced before the intrinsic headers are first included (the porosity stage's scalar
// path reaches them through the lanes' exp and log).
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ < 13
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif
#include <benchmark/benchmark.h>

#include <algorithm>
#include <random>
#include <type_traits>
#include <vector>

#include "constitutive/composed_kernel.hpp"
#include "damage/grady_kipp.hpp"
#include "eos/ideal_gas.hpp"
#include "eos/linear_elastic.hpp"
#include "eos/mie_gruneisen.hpp"
#include "eos/tillotson.hpp"
#include "strength/drucker_prager.hpp"
#include "strength/elastic.hpp"
#include "strength/hydro.hpp"
#include "strength/j2_plasticity.hpp"
#include "strength/modified_lundborg.hpp"
#include "support/bodies.hpp"
#include "xsimd/memory/xsimd_aligned_allocator.hpp"

namespace {

using namespace shatter;

// Columns of a basalt-like block under random small strain increments (some yielding, some in
// each Tillotson region through a spread of density and energy).
struct Columns {
  using Vec = std::vector<double, xsimd::aligned_allocator<double, 64>>;
  Vec data[36];
  constitutive::ConstitutiveColumns c;

  Columns(std::size_t n, double rho0, double e_scale, bool damage = false) {
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (auto& v : data) v.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      data[0][i] = rho0 * (1.0 + 0.2 * u(rng));
      data[1][i] = 1e-9;
      data[2][i] = e_scale * (1.0 + u(rng));
      for (int k = 3; k < 9; ++k) data[k][i] = 1e8 * u(rng);
      for (int k = 11; k < 17; ++k) data[k][i] = 2e-4 * u(rng);
      for (int k = 17; k < 20; ++k) data[k][i] = 1e-4 * u(rng);
    }
    c.rho = data[0].data();
    c.mass = data[1].data();
    c.energy = data[2].data();
    for (int k = 0; k < 6; ++k) c.stress[k] = data[3 + k].data();
    c.pressure = data[9].data();
    c.soundspeed = data[10].data();
    for (int k = 0; k < 6; ++k) c.deps[k] = data[11 + k].data();
    for (int k = 0; k < 3; ++k) c.dspin[k] = data[17 + k].data();
    c.plastic_strain = data[20].data();
    c.heat = data[21].data();
    if (damage) {
      // Undamaged deviator and a Weibull flaw population (basalt-like thresholds ~1e-4, so
      // tensile particles grow damage every step).
      for (std::size_t i = 0; i < n; ++i) {
        for (int k = 0; k < 6; ++k) data[22 + k][i] = data[3 + k][i];
        data[28][i] = 0.0;                          // damage
        data[29][i] = 5e-5 * (1.0 + 0.5 * u(rng));  // eps_min
        data[30][i] = 3e-4;                         // eps_max
        data[31][i] = 20.0;                         // n_flaws
        data[32][i] = 8.5;                          // weibull_m
      }
      for (int k = 0; k < 6; ++k) c.sdev[k] = data[22 + k].data();
      for (int k = 0; k < 6; ++k) c.damage_state[k] = data[28 + k].data();
    }
  }
};

const auto kEl = strength::ElasticConstants::from_young_poisson(53.1e9, 0.15);
const eos::Tillotson kBasalt({2700.0, 26.7e9, 26.7e9, 0.5, 1.5, 487e6, 4.72e6, 18.2e6, 2000.0, 5.0,
                              5.0});

template <class Kernel>
void run(benchmark::State& state, const Kernel& k, double rho0, double e_scale) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const bool use_simd = state.range(1) != 0;
  Columns cols(n, rho0, e_scale, Kernel::kDamaged);
  if constexpr (std::decay_t<decltype(k.porosity())>::kEnabled) {
    // Distension spread over the crush range, the density of the bulk (rho0 / alpha) around it.
    std::mt19937_64 rng(2);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const double a0 = k.porosity().alpha0();
    for (std::size_t i = 0; i < n; ++i) {
      cols.data[34][i] = 1.0 + (a0 - 1.0) * u(rng);
      cols.data[0][i] *= 1.0 / cols.data[34][i];
    }
    cols.c.distension = cols.data[34].data();
    cols.c.compaction_heat = cols.data[35].data();
  }
  const constitutive::StepParams sp{1e-7, 1e-3, 0.5, 2.0};
  for (auto _ : state) {
    k.update(cols.c, 0, n, sp, use_simd);
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(n));
  state.SetLabel(use_simd ? "simd" : "scalar");
}

void BM_Tillotson_LinearHardening(benchmark::State& s) {
  const constitutive::ComposedKernel<eos::Tillotson, strength::J2Plasticity, damage::NoDamage> k(
      kBasalt, {kEl, 3.5e9, 5.31e6}, {});
  run(s, k, 2700.0, 5e6);
}
void BM_Tillotson_LinearHardening_GradyKipp(benchmark::State& s) {
  const constitutive::ComposedKernel<eos::Tillotson, strength::J2Plasticity, damage::GradyKipp> k(
      kBasalt, {kEl, 3.5e9, 5.31e6}, {});
  run(s, k, 2700.0, 5e6);
}
void BM_Tillotson_ModifiedLundborg(benchmark::State& s) {
  const constitutive::ComposedKernel<eos::Tillotson, strength::ModifiedLundborg, damage::NoDamage>
      k(kBasalt, {kEl, 90e6, 1.5, 0.8, 1500e6, 0.256, 3.4e6}, {});
  run(s, k, 2700.0, 5e6);
}
void BM_Tillotson_DruckerPrager(benchmark::State& s) {
  const constitutive::ComposedKernel<eos::Tillotson, strength::DruckerPrager, damage::NoDamage> k(
      kBasalt, {kEl, 50e6, 0.6, 0.2, -30e6}, {});
  run(s, k, 2700.0, 5e6);
}
void BM_Tillotson_Hydro(benchmark::State& s) {
  const constitutive::ComposedKernel<eos::Tillotson, strength::Hydro, damage::NoDamage> k(kBasalt,
                                                                                          {}, {});
  run(s, k, 2700.0, 5e6);
}
void BM_MieGruneisen_Hydro(benchmark::State& s) {
  const constitutive::ComposedKernel<eos::MieGruneisen, strength::Hydro, damage::NoDamage> k(
      eos::MieGruneisen({2703.0, 5240.0, 1.4, 1.97}), {}, {});
  run(s, k, 2703.0, 1e5);
}
void BM_LinearElastic_Elastic(benchmark::State& s) {
  const constitutive::ComposedKernel<eos::LinearElastic, strength::Elastic, damage::NoDamage> k(
      eos::LinearElastic({2700.0, kEl.K}), {kEl}, {});
  run(s, k, 2700.0, 0.0);
}
void BM_IdealGas_Hydro(benchmark::State& s) {
  const constitutive::ComposedKernel<eos::IdealGas, strength::Hydro, damage::NoDamage> k(
      eos::IdealGas({1.0, 1.4}), {}, {});
  run(s, k, 1.0, 2.5);
}

// The porosity stage (issue 29, kernels/porosity): eps-alpha (closed form) and P-alpha (the ITP
// root solve where a point compacts) on the Tillotson / hydro kernel above.
void BM_Tillotson_Hydro_EpsAlpha(benchmark::State& s) {
  const auto por = porosity::Porous::eps_alpha({1.5, -1e-5, 0.98, 1.0, -0.1}, 2700.0);
  const constitutive::ComposedKernel<eos::Tillotson, strength::Hydro, damage::NoDamage,
                                     porosity::Porous>
      k(kBasalt, {}, {}, constitutive::kDefaultCoupling, por);
  run(s, k, 2700.0, 5e6);
}
void BM_Tillotson_Hydro_PAlpha(benchmark::State& s) {
  const auto por = porosity::Porous::p_alpha({1.5, 1e6, 1e9, 2.0, 1000.0});
  const constitutive::ComposedKernel<eos::Tillotson, strength::Hydro, damage::NoDamage,
                                     porosity::Porous>
      k(kBasalt, {}, {}, constitutive::kDefaultCoupling, por);
  run(s, k, 2700.0, 5e6);
}

// JBM09's two-stage curve with pumice's fit (data/materials.toml `pumice`: alpha0 4.64, p_e 1 MPa,
// p_t 68 MPa, alpha_t 1.9, p_s 213 MPa, exponents 12 and 3: integer powers by products).
void BM_Tillotson_Hydro_PAlphaTwoStage(benchmark::State& s) {
  porosity::PAlphaParams q;
  q.alpha0 = 4.64;
  q.p_e = 1.0e6;
  q.p_s = 2.13e8;
  q.n = 12.0;
  q.p_t = 6.8e7;
  q.alpha_t = 1.9;
  q.n2 = 3.0;
  const constitutive::ComposedKernel<eos::Tillotson, strength::Hydro, damage::NoDamage,
                                     porosity::Porous>
      k(kBasalt, {}, {}, constitutive::kDefaultCoupling, porosity::Porous::p_alpha(q));
  run(s, k, 2700.0, 5e6);
}

// The laboratory impact's target (scenes/lab-impact-coarse.toml: basalt of Table 1, Tillotson,
// linear hardening, Grady-Kipp) as the stage sees it at 0-25 us, drawn from the per-lane counts
// of docs/performance.md ("Session 22: constitutive update"): 56 % of the lanes compressed, the
// rest cold expanded (E below E_iv, so no batch needs Eqs. 9-10), deviators of 1-100 MPa (a
// few per cent of the lanes above the 3.5 GPa yield), and damage by blocks of 8 consecutive
// points as neighbours in the store have it: 31 % of the blocks fully damaged, 45 % intact,
// the rest mixed. The state is restored before every iteration (not timed), so every iteration
// sees the same mix.
void BM_LabImpactLike(benchmark::State& state) {
  const constitutive::ComposedKernel<eos::Tillotson, strength::J2Plasticity, damage::GradyKipp> k(
      kBasalt, {kEl, 3.5e9, 5.31e6}, {});
  const auto n = static_cast<std::size_t>(state.range(0));
  const bool use_simd = state.range(1) != 0;
  Columns cols(n, 2700.0, 0.0, true);
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (std::size_t b = 0; b < n; b += 8) {
    const double kind = u(rng);
    for (std::size_t i = b; i < std::min(n, b + 8); ++i) {
      const bool compressed = u(rng) < 0.56;
      cols.data[0][i] = 2700.0 * (compressed ? 1.0 + 0.02 * u(rng) : 1.0 - 0.02 * u(rng));
      cols.data[2][i] = 0.3 * 4.72e6 * u(rng);
      const double scale = u(rng) < 0.03 ? 4e9 : 1e7 + 9e7 * u(rng);
      const double p = (compressed ? 1.0 : -0.3) * 1e8 * u(rng);
      double dev[6];
      for (double& x : dev) x = scale * (2.0 * u(rng) - 1.0);
      const double m = (dev[0] + dev[1] + dev[2]) / 3.0;
      for (int c = 0; c < 3; ++c) dev[c] -= m;
      for (int c = 0; c < 6; ++c) {
        cols.data[22 + c][i] = dev[c];
        cols.data[3 + c][i] = dev[c] - (c < 3 ? p : 0.0);
      }
      for (int c = 11; c < 17; ++c) cols.data[c][i] = 2e-5 * (2.0 * u(rng) - 1.0);
      const bool failed = kind < 0.31 || (kind >= 0.76 && u(rng) < 0.45);
      cols.data[28][i] = failed ? 1.0 : 0.0;
    }
  }
  Columns::Vec saved[36];
  for (int c = 0; c < 36; ++c) saved[c] = cols.data[c];
  const constitutive::StepParams sp{1e-7, 2.4e-3, 0.5, 2.0};
  for (auto _ : state) {
    state.PauseTiming();
    for (int c = 0; c < 36; ++c) std::copy(saved[c].begin(), saved[c].end(), cols.data[c].begin());
    state.ResumeTiming();
    k.update(cols.c, 0, n, sp, use_simd);
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(n));
  state.SetLabel(use_simd ? "simd" : "scalar");
}

void sizes(benchmark::internal::Benchmark* b) {
  for (int64_t n : shatter::bench::particle_counts({100000, 1000000})) {
    for (int64_t simd : {0, 1}) b->Args({n, simd});
  }
  b->ArgNames({"n", "simd"})->Unit(benchmark::kMillisecond);
}

BENCHMARK(BM_Tillotson_LinearHardening)->Apply(sizes);
BENCHMARK(BM_Tillotson_LinearHardening_GradyKipp)->Apply(sizes);
BENCHMARK(BM_LabImpactLike)->Apply(sizes);
BENCHMARK(BM_Tillotson_ModifiedLundborg)->Apply(sizes);
BENCHMARK(BM_Tillotson_DruckerPrager)->Apply(sizes);
BENCHMARK(BM_Tillotson_Hydro)->Apply(sizes);
BENCHMARK(BM_Tillotson_Hydro_EpsAlpha)->Apply(sizes);
BENCHMARK(BM_Tillotson_Hydro_PAlpha)->Apply(sizes);
BENCHMARK(BM_Tillotson_Hydro_PAlphaTwoStage)->Apply(sizes);
BENCHMARK(BM_MieGruneisen_Hydro)->Apply(sizes);
BENCHMARK(BM_LinearElastic_Elastic)->Apply(sizes);
BENCHMARK(BM_IdealGas_Hydro)->Apply(sizes);

}  // namespace

BENCHMARK_MAIN();
