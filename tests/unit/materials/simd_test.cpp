// Every constitutive kernel gives the same answer on the SIMD path (xsimd::batch<double>) as on
// the scalar reference path, lane by lane.

// GCC 12 false positive inside AVX-512 intrinsics (PR 105593), see constitutive/simd.hpp; it
// must be silenced before the intrinsic headers are first included (the Grady-Kipp policy's
// vectorised exp and log reach them here).
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ < 13
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "constitutive/composed_kernel.hpp"
#include "damage/brittle.hpp"
#include "damage/grady_kipp.hpp"
#include "eos/ideal_gas.hpp"
#include "eos/linear_elastic.hpp"
#include "eos/linear_polynomial.hpp"
#include "eos/mie_gruneisen.hpp"
#include "eos/tillotson.hpp"
#include "eos/tillotson_simplified.hpp"
#include "material_test_support.hpp"
#include "strength/benz_asphaug.hpp"
#include "strength/drucker_prager.hpp"
#include "strength/elastic.hpp"
#include "strength/hydro.hpp"
#include "strength/j2_plasticity.hpp"
#include "strength/lundborg.hpp"
#include "strength/modified_lundborg.hpp"

namespace shatter {
namespace {

using simd::Batch;
constexpr std::size_t W = simd::kWidth;

// Tolerance: 64 ulp of the larger magnitude, floored at 64 ulp of the quantity's natural scale.
// Both paths run the same formulas in the same order, but (a) GCC contracts a*b + c into FMA on
// the scalar path (C++ defaults to -ffp-contract=fast) and not always on the intrinsic batch
// path, and (b) xsimd's vectorised exp differs from libm's by <= 1 ulp. Each is an ulp-level
// change of a term; the sum of Eq. 12 (dp/drho + p/rho^2 dp/dE) and the mixing interpolation of
// Eq. 10 cancel terms up to ~10 times larger than the result, so a few tens of ulp of the
// natural scale is the honest bound. Measured worst case: ~20 ulp (Release); the sanitizer
// build (different inlining and contraction) reached ~150 ulp of the *result* where Eq. 12
// cancels two terms 100 times larger, hence the term-based scales in check_eos.
constexpr double kUlps = 64.0;
::testing::AssertionResult close(double simd, double scalar, double scale) {
  const double tol = kUlps * std::numeric_limits<double>::epsilon() *
                     std::max({std::abs(simd), std::abs(scalar), scale});
  if (std::abs(simd - scalar) <= tol || (std::isnan(simd) && std::isnan(scalar))) {
    return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure() << "simd " << simd << " scalar " << scalar << " differ by "
                                       << std::abs(simd - scalar) << " > " << tol;
}

template <class Eos>
void check_eos(const Eos& eos, double rho0, double e_max, double p_scale) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> lr(-3.0, std::log10(3.0));
  std::uniform_real_distribution<double> ue(-0.05, 1.0);
  for (int trial = 0; trial < 2000; ++trial) {
    alignas(64) double rho[W], e[W], p[W], c2[W];
    for (std::size_t l = 0; l < W; ++l) {
      rho[l] = rho0 * std::pow(10.0, lr(rng));
      e[l] = e_max * ue(rng);
    }
    const auto b = eos.evaluate(Batch::load_aligned(rho), Batch::load_aligned(e));
    b.p.store_aligned(p);
    b.c2.store_aligned(c2);
    for (std::size_t l = 0; l < W; ++l) {
      const auto s = eos.evaluate(rho[l], e[l]);
      // Natural scales are those of the terms being summed, not of the result: the cold and
      // thermal parts of p are ~ p_scale and ~ 2 rho E (Grüneisen factor <= 2); the two terms of
      // Eq. 12 are ~ (|p| + p_scale) / rho times a Grüneisen factor. In strongly expanded hot
      // states they cancel to 1% of their size (Mie–Grüneisen at rho = 0.3 rho0), which the
      // scale must not hide.
      const double ps = p_scale + 2.0 * rho[l] * std::abs(e[l]);
      const double cs = 4.0 * (std::abs(s.p) + p_scale) / rho[l];
      ASSERT_TRUE(close(p[l], s.p, ps)) << "rho=" << rho[l] << " E=" << e[l];
      ASSERT_TRUE(close(c2[l], s.c2, cs)) << "rho=" << rho[l] << " E=" << e[l];
    }
  }
}

TEST(SimdEqualsScalar, Tillotson) {
  check_eos(eos::Tillotson(test::basalt_tillotson()), 2700.0, 10 * 18.2e6, 26.7e9);
}
TEST(SimdEqualsScalar, TillotsonSimplified) {
  check_eos(eos::TillotsonSimplified({2700.0, 26.7e9, 0.5, 1.5}), 2700.0, 1e8, 26.7e9);
}
TEST(SimdEqualsScalar, MieGruneisen) {
  check_eos(eos::MieGruneisen({2703.0, 5240.0, 1.4, 1.97}), 2703.0, 1e8, 7.4e10);
}
TEST(SimdEqualsScalar, LinearPolynomial) {
  eos::LinearPolynomialParams q;
  q.rho0 = 2000.0;
  const double C[7] = {1e5, 30e9, 10e9, 5e9, 0.4, 0.3, 0.2};
  for (int k = 0; k < 7; ++k) q.C[k] = C[k];
  check_eos(eos::LinearPolynomial(q), 2000.0, 1e7, 30e9);
}
TEST(SimdEqualsScalar, LinearElasticAndIdealGas) {
  check_eos(eos::LinearElastic({2700.0, 30e9}), 2700.0, 1e6, 30e9);
  check_eos(eos::IdealGas({1.0, 1.4}), 1.0, 10.0, 1.0);
}

// Strength kernels: random deviators and pressures through return_map on both paths.
// heat_scale: size of the two terms of Eq. 40 that the heat increment sums (per unit mass),
// tau dtau / G and p dp / K, ~ stress_scale^2 / (G rho); they cancel where dilatancy stores work.
// strain_scale: that of tau*/G, from which the plastic strain increment (tau* - tau)/G cancels.
template <class Model>
void check_strength(const Model& m, double stress_scale, double heat_scale = 1e3,
                    double strain_scale = 1e-2) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 2000; ++trial) {
    alignas(64) double s[6][W], p[W], d[W], q[W];
    for (std::size_t l = 0; l < W; ++l) {
      for (int k = 0; k < 6; ++k) s[k][l] = stress_scale * u(rng);
      p[l] = 3.0 * stress_scale * u(rng);
      d[l] = 0.5 * (1.0 + u(rng));
      q[l] = 2e6 * (1.0 + u(rng));
    }
    Batch sb[6];
    for (int k = 0; k < 6; ++k) sb[k] = Batch::load_aligned(s[k]);
    strength::PlasticState<Batch> stb{Batch::load_aligned(p),
                                      Batch(0.01),
                                      Batch::load_aligned(q),
                                      Batch::load_aligned(d),
                                      Batch(2700.0),
                                      Batch(1e6),
                                      Batch(0.0)};
    m.return_map(sb, stb);
    alignas(64) double out_s[6][W], out_p[W], out_h[W], out_e[W];
    for (int k = 0; k < 6; ++k) sb[k].store_aligned(out_s[k]);
    stb.p.store_aligned(out_p);
    stb.heat.store_aligned(out_h);
    stb.eps_p.store_aligned(out_e);
    for (std::size_t l = 0; l < W; ++l) {
      double ss[6];
      for (int k = 0; k < 6; ++k) ss[k] = s[k][l];
      strength::PlasticState<double> st{p[l], 0.01, q[l], d[l], 2700.0, 1e6, 0.0};
      m.return_map(ss, st);
      for (int k = 0; k < 6; ++k) ASSERT_TRUE(close(out_s[k][l], ss[k], stress_scale)) << k;
      ASSERT_TRUE(close(out_p[l], st.p, stress_scale));
      ASSERT_TRUE(close(out_h[l], st.heat, heat_scale));
      ASSERT_TRUE(close(out_e[l], st.eps_p, strain_scale));
    }
  }
}

const auto kEl = strength::ElasticConstants::from_young_poisson(53.1e9, 0.15);

TEST(SimdEqualsScalar, StrengthModels) {
  check_strength(strength::Hydro{}, 1e9);
  check_strength(strength::Elastic{kEl}, 1e9);
  check_strength(strength::J2Plasticity{kEl, 3.5e9, 5.31e6}, 3e9);
  check_strength(strength::BenzAsphaug{kEl, 3.5e9}, 3e9);
  check_strength(strength::DruckerPrager{kEl, 50e6, 0.6, 0.2, -30e6}, 300e6);
  check_strength(strength::Lundborg{kEl, 90e6, 1.5, 0.8, 1500e6, 3.4e6}, 1e9);
  check_strength(strength::ModifiedLundborg{kEl, 90e6, 1.5, 0.8, 1500e6, 0.256, 3.4e6}, 1e9);
}

TEST(SimdEqualsScalar, StrengthModelsAtStiffExtremeStates) {
  // E_Y = 1e3 GPa with deviators and pressures up to ~1 TPa (ISSUE materials, stiff and extreme
  // states): the clamps (tensile limits, dl <= tau*/G) and the fixed Newton count of the modified
  // Lundborg corrector take different branches lane by lane here, which the 1 GPa sweep above
  // does not reach. Same ulp bound: the formulas are the same, only the magnitudes change.
  const auto stiff = strength::ElasticConstants::from_young_poisson(1e12, 0.25);
  // Eq. 40's two terms are ~ (1 TPa)^2 / (G rho) = 1e9 J/kg here and cancel to ~1e6 J/kg in the
  // dilatant Lundborg returns (measured: SIMD and scalar heat differ by 250 ulp of the result,
  // 0.1 ulp of the terms), so the heat is compared on the scale of the terms; likewise the
  // plastic strain, whose increment (tau* - tau)/G cancels from tau*/G ~ 2.5.
  const double q = 1e12 * 1e12 / (stiff.G * 2700.0);
  const double e = 1e12 / stiff.G;
  check_strength(strength::J2Plasticity{stiff, 3.5e9, 5.31e6}, 1e12, q, e);
  check_strength(strength::BenzAsphaug{stiff, 3.5e9}, 1e12, q, e);
  check_strength(strength::DruckerPrager{stiff, 50e6, 0.6, 0.2, -30e6}, 1e12, q, e);
  check_strength(strength::Lundborg{stiff, 90e6, 1.5, 0.8, 1500e6, 3.4e6}, 1e12, q, e);
  check_strength(strength::ModifiedLundborg{stiff, 90e6, 1.5, 0.8, 1500e6, 0.256, 3.4e6}, 1e12, q,
                 e);
}

// The whole composed kernel over a column range with a tail (n not a multiple of the width):
// Jaumann trial, EOS, return mapping, artificial viscosity and the energy iteration together.
// rho0, e0 and s0 set the magnitudes of density, energy and stress of the random states.
// With a damage policy (Kernel::kDamaged) the undamaged deviator (sdev, columns 22-27) and the
// damage state (28-33: D, eps_min, eps_max, n_flaws, m_p, n_active) are random too: D in [0, 1)
// with a quarter of the points at 0 and an eighth at 1, flaw thresholds around the strains of
// the random stresses so that damage grows in some points and not in others.
template <class Kernel>
void check_composed(const Kernel& kernel, double rho0, double e0, double s0) {
  const std::size_t n = 8 * W + 3;
  struct Store {
    std::vector<double> c[40];
  };
  auto make = [&](unsigned seed) {
    Store st;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (auto& v : st.c) v.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      st.c[0][i] = rho0 * (1.0 + 0.3 * u(rng));                  // rho
      st.c[1][i] = 1e-3;                                         // mass
      st.c[2][i] = e0 * (1.0 + u(rng));                          // energy
      for (int k = 3; k < 9; ++k) st.c[k][i] = s0 * u(rng);      // stress
      for (int k = 11; k < 17; ++k) st.c[k][i] = 1e-3 * u(rng);  // deps
      for (int k = 17; k < 20; ++k) st.c[k][i] = 1e-3 * u(rng);  // dspin
      st.c[20][i] = 0.1 * (1.0 + u(rng));                        // plastic strain
      st.c[21][i] = 1e6 * (1.0 + u(rng));                        // heat
      for (int k = 22; k < 28; ++k) st.c[k][i] = s0 * u(rng);    // sdev
      const double d = 0.5 * (1.0 + u(rng));
      st.c[28][i] = i % 4 == 0 ? 0.0 : (i % 8 == 1 ? 1.0 : d);  // damage
      st.c[29][i] = 2e-3 * (1.0 + u(rng)) * s0 / 1e9;           // eps_min
      st.c[30][i] = 1.3 * st.c[29][i];                          // eps_max
      st.c[31][i] = 4000.0;                                     // n_flaws
      st.c[32][i] = std::log(4000.0) / std::log(1.3);           // weibull_m
    }
    return st;
  };
  auto columns = [](Store& st) {
    constitutive::ConstitutiveColumns c;
    c.rho = st.c[0].data();
    c.mass = st.c[1].data();
    c.energy = st.c[2].data();
    for (int k = 0; k < 6; ++k) c.stress[k] = st.c[3 + k].data();
    c.pressure = st.c[9].data();
    c.soundspeed = st.c[10].data();
    for (int k = 0; k < 6; ++k) c.deps[k] = st.c[11 + k].data();
    for (int k = 0; k < 3; ++k) c.dspin[k] = st.c[17 + k].data();
    c.plastic_strain = st.c[20].data();
    c.heat = st.c[21].data();
    if constexpr (Kernel::kDamaged) {
      for (int k = 0; k < 6; ++k) c.sdev[k] = st.c[22 + k].data();
      for (int k = 0; k < 6; ++k) c.damage_state[k] = st.c[28 + k].data();
    }
    return c;
  };
  const constitutive::StepParams sp{1e-7, 1e-3, 0.5, 2.0};
  Store a = make(3), b = make(3);
  kernel.update(columns(a), 1, n, sp, true);  // unaligned start: exercises the unaligned loads
  kernel.update(columns(b), 1, n, sp, false);
  // Pressure and stress on the stress scale (or the EOS's, whichever is larger), energy on its
  // own, sound speed on sqrt(stress / rho).
  const double ps = std::max(s0, rho0 * e0);
  double scales[34] = {1, 1, e0, ps, ps, ps, ps, ps, ps, ps,   std::sqrt(ps / rho0),
                       1, 1, 1,  1,  1,  1,  1,  1,  1,  1e-2, 1e3};
  for (int k = 22; k < 28; ++k) scales[k] = ps;
  scales[28] = 1.0;  // damage
  std::vector<int> cols{2, 3, 4, 5, 6, 7, 8, 9, 10, 20, 21};
  if constexpr (Kernel::kDamaged) {
    for (int k = 22; k < 29; ++k) cols.push_back(k);
  }
  for (int col : cols) {
    for (std::size_t i = 0; i < n; ++i) {
      ASSERT_TRUE(close(a.c[col][i], b.c[col][i], scales[col])) << "column " << col << " p " << i;
    }
  }
}

TEST(SimdEqualsScalar, ComposedKernelWithArtificialViscosity) {
  check_composed(
      constitutive::ComposedKernel<eos::Tillotson, strength::ModifiedLundborg, damage::NoDamage>(
          eos::Tillotson(test::basalt_tillotson()),
          strength::ModifiedLundborg{kEl, 90e6, 1.5, 0.8, 1500e6, 0.256, 3.4e6}, {}),
      2700.0, 5e6, 1e9);
}

TEST(SimdEqualsScalar, ComposedKernelOtherModelPairs) {
  // Each EOS once through the whole kernel (the energy iteration of App. A step 7 evaluates the
  // EOS twice per point), with a strength model of a different kind each.
  const auto al = strength::ElasticConstants::from_young_poisson(69e9, 0.33);
  check_composed(
      constitutive::ComposedKernel<eos::MieGruneisen, strength::J2Plasticity, damage::NoDamage>(
          eos::MieGruneisen({2703.0, 5240.0, 1.4, 1.97}), strength::J2Plasticity{al, 300e6, 1e9},
          {}),
      2703.0, 1e6, 1e9);
  check_composed(constitutive::ComposedKernel<eos::TillotsonSimplified, strength::DruckerPrager,
                                              damage::NoDamage>(
                     eos::TillotsonSimplified({2700.0, 26.7e9, 0.5, 1.5}),
                     strength::DruckerPrager{kEl, 50e6, 0.6, 0.2, -30e6}, {}),
                 2700.0, 1e6, 300e6);
  check_composed(constitutive::ComposedKernel<eos::IdealGas, strength::Hydro, damage::NoDamage>(
                     eos::IdealGas({1.0, 1.4}), strength::Hydro{}, {}),
                 1.0, 2.5, 0.0);
  check_composed(
      constitutive::ComposedKernel<eos::LinearElastic, strength::BenzAsphaug, damage::NoDamage>(
          eos::LinearElastic({2700.0, 30e9}), strength::BenzAsphaug{kEl, 1e9}, {}),
      2700.0, 1e5, 1e9);
}

// Damaged kernels in each damage-stress coupling (issue 11): total, incremental (lane-wise
// (1 - D) G in the trial) and lagged, with a strength model that carries D in its yield surface
// (modified Lundborg: borne deviator, intact-equivalent stress for Eq. 18, shear fraction from
// Y(p, D)) and one that does not (J2), and with brittle and Grady-Kipp damage.
TEST(SimdEqualsScalar, ComposedKernelWithDamageInEachCoupling) {
  using constitutive::DamageCoupling;
  damage::GradyKipp gk;
  damage::Brittle brittle;
  brittle.params.sigma_0 = 40e6;
  for (auto c : {DamageCoupling::total, DamageCoupling::incremental, DamageCoupling::lagged}) {
    SCOPED_TRACE(std::string(constitutive::coupling_name(c)));
    check_composed(
        constitutive::ComposedKernel<eos::Tillotson, strength::ModifiedLundborg, damage::GradyKipp>(
            eos::Tillotson(test::basalt_tillotson()),
            strength::ModifiedLundborg{kEl, 60e6, 1.5, 0.8, 3500e6, 0.256, 3.4e6}, gk, c),
        2700.0, 5e6, 1e8);
    check_composed(
        constitutive::ComposedKernel<eos::Tillotson, strength::J2Plasticity, damage::GradyKipp>(
            eos::Tillotson(test::basalt_tillotson()), strength::J2Plasticity{kEl, 3.5e9, 5.31e6},
            gk, c),
        2700.0, 5e6, 1e8);
    check_composed(
        constitutive::ComposedKernel<eos::MieGruneisen, strength::Lundborg, damage::Brittle>(
            eos::MieGruneisen({2703.0, 5240.0, 1.4, 1.97}),
            strength::Lundborg{kEl, 90e6, 1.5, 0.8, 1500e6, 3.4e6}, brittle, c),
        2703.0, 1e6, 1e8);
  }
}

// The per-batch skips of the kernels (a batch computes only what one of its lanes needs) must
// give every lane the bits of the path that does all the work. This file is compiled as the
// library is (no FMA contraction, tests/CMakeLists.txt), so both paths round alike here too.
TEST(BatchSkips, TillotsonWithoutHotLanesKeepsTheAllBranchesBits) {
  // evaluate() computes Eqs. 9-10 (two exp) only in a batch with a lane in the hot or mixing
  // region. Batches drawn from the compressed, cold expanded and vapour regions only (skipped)
  // and from all five (computed; with a forced skip their hot and mixed lanes would take
  // Eq. 8's value). Bound: bitwise equality of p and c^2 against kAllBranches, batch and scalar
  // path; the counts show both kinds of batch.
  const eos::Tillotson eos(test::basalt_tillotson());
  const auto& q = eos.params();
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int cold_only = 0, with_hot = 0;
  for (int rep = 0; rep < 4000; ++rep) {
    const bool cold = rep % 2 == 0;
    alignas(64) double rho[W], e[W];
    for (std::size_t l = 0; l < W; ++l) {
      rho[l] = q.rho0 * (0.3 + 1.0 * u(rng));
      e[l] = cold ? (rho[l] >= q.rho0 ? 3.0 : 1.0) * q.Eiv * u(rng) : 1.5 * q.Ecv * u(rng);
    }
    const auto a = eos.evaluate(Batch::load_aligned(rho), Batch::load_aligned(e));
    const auto b = eos.evaluate<Batch, true>(Batch::load_aligned(rho), Batch::load_aligned(e));
    alignas(64) double pa[W], pb[W], ca[W], cb[W];
    a.p.store_aligned(pa), b.p.store_aligned(pb), a.c2.store_aligned(ca), b.c2.store_aligned(cb);
    bool hot = false;
    for (std::size_t l = 0; l < W; ++l) {
      const auto r = eos.region(rho[l], e[l]);
      hot = hot || r == eos::TillotsonRegion::hot_expanded || r == eos::TillotsonRegion::mixed;
      const auto sa = eos.evaluate(rho[l], e[l]);
      const auto sb = eos.evaluate<double, true>(rho[l], e[l]);
      for (const double x : {pb[l], sa.p, sb.p})
        ASSERT_EQ(std::bit_cast<std::uint64_t>(pa[l]), std::bit_cast<std::uint64_t>(x))
            << "batch " << rep << " lane " << l;
      for (const double x : {cb[l], sa.c2, sb.c2})
        ASSERT_EQ(std::bit_cast<std::uint64_t>(ca[l]), std::bit_cast<std::uint64_t>(x))
            << "batch " << rep << " lane " << l;
    }
    (hot ? with_hot : cold_only) += 1;
  }
  EXPECT_GT(cold_only, 1000);
  EXPECT_GT(with_hot, 1000);
}

TEST(BatchSkips, J2ReturnOfElasticBatchesKeepsTheReturnsBits) {
  // return_map skips the return in a batch where no lane yields: deviator, plastic strain, its
  // increment and the heat must be those of the return made in every batch (kAllWork).
  // Deviators of 0.1-1.2 times the hardened yield stress, half the batches all below it.
  // Bound: bitwise equality; the counts show both kinds of batch.
  const strength::J2Plasticity j2{strength::ElasticConstants::from_young_poisson(53.1e9, 0.15),
                                  100e6, 5e9};
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int elastic = 0, yielding = 0;
  for (int rep = 0; rep < 4000; ++rep) {
    const double top = rep % 2 == 0 ? 0.95 : 1.2;
    alignas(64) double s[6][W], ep[W], heat[W];
    for (std::size_t l = 0; l < W; ++l) {
      ep[l] = rep % 3 == 0 ? 0.0 : 0.01 * (u(rng) + 1.0);
      heat[l] = 1e3 * (u(rng) + 1.0);
      double d[6];
      for (double& x : d) x = u(rng);
      const double m = (d[0] + d[1] + d[2]) / 3.0;
      for (int k = 0; k < 3; ++k) d[k] -= m;
      const double sbar = std::sqrt(3.0 * strength::j2(d));
      const double target = j2.yield_stress(ep[l]) * (0.1 + (top - 0.1) * 0.5 * (u(rng) + 1.0));
      for (int k = 0; k < 6; ++k) s[k][l] = d[k] * target / sbar;
    }
    Batch sa[6], sb[6];
    for (int k = 0; k < 6; ++k) sa[k] = sb[k] = Batch::load_aligned(s[k]);
    strength::PlasticState<Batch> a{Batch(1e8), Batch::load_aligned(ep), Batch::load_aligned(heat),
                                    Batch(0.0), Batch(2700.0),           Batch(0.0),
                                    Batch(-1.0)};
    strength::PlasticState<Batch> b = a;
    j2.return_map(sa, a);
    j2.return_map<Batch, true>(sb, b);
    alignas(64) double x[9][W], y[9][W];
    for (int k = 0; k < 6; ++k) sa[k].store_aligned(x[k]), sb[k].store_aligned(y[k]);
    a.eps_p.store_aligned(x[6]), a.heat.store_aligned(x[7]), a.deps_p.store_aligned(x[8]);
    b.eps_p.store_aligned(y[6]), b.heat.store_aligned(y[7]), b.deps_p.store_aligned(y[8]);
    bool any_yield = false;
    for (std::size_t l = 0; l < W; ++l) {
      any_yield = any_yield || y[8][l] > 0.0;
      for (int k = 0; k < 9; ++k)
        ASSERT_EQ(std::bit_cast<std::uint64_t>(x[k][l]), std::bit_cast<std::uint64_t>(y[k][l]))
            << "batch " << rep << " lane " << l << " value " << k;
    }
    (any_yield ? yielding : elastic) += 1;
  }
  EXPECT_GT(elastic, 1000);
  EXPECT_GT(yielding, 1000);
}

}  // namespace
}  // namespace shatter
