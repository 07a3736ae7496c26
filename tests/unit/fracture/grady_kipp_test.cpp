// Grady–Kipp damage (MPM paper Eqs. 17–19, BA95 Eq. 22) under imposed uniaxial tension and
// compression, the (1 - D) correction of Eq. 18 applied to the damaged stress of Eq. 14, its
// options, and SIMD against scalar. The policy receives the intact stress (damage_policy.hpp).

// GCC 12 false positive inside AVX-512 intrinsics (PR 105593), see constitutive/simd.hpp: the
// batch tests inline xsimd's cbrt, exp and log; silenced before the intrinsic headers.
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ < 13
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>

#include "damage/grady_kipp.hpp"
#include "unit/fracture/lattice.hpp"

namespace shatter::damage {
namespace {

constexpr double kYoung = 53.1e9;   // basalt, MPM paper Table 1
constexpr double kSound = 5000.0;   // m/s
constexpr double kVolume = 1.0e-9;  // (1 mm)^3 particle
const double kRadius = std::cbrt(3.0 * kVolume / (4.0 * std::numbers::pi));  // R_s default
const double kRate = 0.4 * kSound / kRadius;                                 // c_g / R_s (Eq. 19)

DamageInput<double> uniaxial(double sigma, double dt) {
  DamageInput<double> in{};
  in.s[0] = sigma;
  in.young = kYoung;
  in.soundspeed = kSound;
  in.volume = kVolume;
  in.dt = dt;
  return in;
}

DamageState<double> flaws(double eps_min, double m_p, double n_f) {
  DamageState<double> st{};
  st.eps_min = eps_min;
  st.n_flaws = n_f;
  st.weibull_m = m_p;
  st.eps_max = n_f > 1.0 ? eps_min * std::pow(n_f, 1.0 / m_p) : eps_min;
  return st;
}

TEST(GradyKipp, SingleFlawCubeRootOfDamageGrowsLinearlyAtCgOverRs) {
  // One flaw: n_act = 1 once eps_eff >= eps_min, so D^(1/3) = c_g/R_s (t - t_on) exactly (Eq.
  // 19) until the cap (n_act/n_f)^(1/3) = 1. The imposed stress sigma = E eps_dot t reaches
  // eps_min at t_on = eps_min / eps_dot. Tolerance 1e-12 relative: one cbrt/cube round trip per
  // step (~2 ulp) accumulated over < 1000 steps.
  const GradyKipp gk{};
  DamageState<double> st = flaws(1.0e-4, 0.0, 1.0);
  const double eps_dot = 1.0e4, dt = 1.0e-9;
  int active_steps = 0;
  for (int n = 1; n <= 1000; ++n) {
    const double t = n * dt;
    const double eps = eps_dot * t;
    // Uniaxial tension: Eq. 18 on the damaged stress of Eq. 14 is the intact strain eps.
    const bool active = eps >= st.eps_min;
    gk.evolve(uniaxial(kYoung * eps, dt), st);
    if (active) ++active_steps;
    const double expected = std::min(active_steps * kRate * dt, 1.0);
    ASSERT_NEAR(std::cbrt(st.damage), expected, 1e-12 * std::max(expected, 1e-300)) << "step " << n;
    ASSERT_EQ(st.n_active, active ? 1.0 : 0.0);
  }
  EXPECT_EQ(st.damage, 1.0);
  EXPECT_GT(active_steps, 0);
}

TEST(GradyKipp, ManyFlawsGrowAtNactCgOverRsUpToTheCap) {
  // n_f = 1e6 flaws with m_p = 8 between eps_min and eps_max = 1e6^(1/8) eps_min. Each step must
  // add n_act c_g / R_s dt to D^(1/3), with n_act = (eps_eff/eps_min)^m_p from Eq. 18 evaluated
  // with the damage at the start of the step, unless D hits the cap (n_act/n_f)^(1/3) (BA95
  // Eq. 22). Tolerance 1e-12 relative: pow/exp/log and cbrt round-off.
  const GradyKipp gk{};
  const double eps_min = 1.0e-4;
  // Many flaws keep the cap low at onset ((1/n_f)^(1/3) = 0.01) and the slow load (0.2% of
  // eps_min per step) lets growth reach it.
  const double n_f = 1.0e6;
  DamageState<double> st = flaws(eps_min, 8.0, n_f);
  const double eps_dot = 100.0, dt = 2.0e-9;
  bool capped_once = false;
  for (int n = 1; n <= 20000 && st.damage < 1.0; ++n) {
    const double sigma = kYoung * eps_dot * n * dt;
    const double d_old = st.damage;
    // Eq. 18: sigma_max of Eq. 14 is (1 - D) sigma in uniaxial tension, so eps_eff = sigma / E.
    const double eps_eff = sigma / kYoung;
    const double n_act =
        eps_eff >= eps_min ? std::min(std::pow(eps_eff / eps_min, 8.0), n_f) : 0.0;  // Eq. 17
    gk.evolve(uniaxial(sigma, dt), st);
    ASSERT_NEAR(st.n_active, n_act, 1e-12 * std::max(n_act, 1.0));
    const double cap = std::cbrt(n_act / n_f);
    const double grown = std::pow(std::cbrt(d_old) + n_act * kRate * dt, 3.0);
    const double expected = std::max(d_old, std::min(grown, cap));
    ASSERT_NEAR(st.damage, expected, 1e-12 * std::max(expected, 1e-300)) << "step " << n;
    // The cap holds exactly for the kernel's own n_act (which may differ from ours by round-off).
    ASSERT_LE(st.damage, std::cbrt(st.n_active / n_f) * (1.0 + 1e-15) + 1e-300);
    if (grown > cap && cap < 1.0) capped_once = true;
  }
  EXPECT_TRUE(capped_once) << "the cap of BA95 Eq. 22 was never exercised";
  EXPECT_EQ(st.damage, 1.0) << "all flaws active must allow full damage";
}

TEST(GradyKipp, NoGrowthUnderCompression) {
  // Uniaxial and hydrostatic compression and shear-free lateral confinement: the largest
  // principal stress is <= 0, so eps_eff = 0 and no flaw activates, however long the load lasts.
  const GradyKipp gk{};
  for (const auto& s : {std::array<double, 6>{-1e9, 0, 0, 0, 0, 0},
                        std::array<double, 6>{-1e9, -1e9, -1e9, 0, 0, 0},
                        std::array<double, 6>{-2e9, -1e9, -1e9, 1e8, 0, 0}}) {
    DamageState<double> st = flaws(1.0e-6, 8.0, 1000.0);
    DamageInput<double> in = uniaxial(0.0, 1e-7);
    for (int c = 0; c < 6; ++c) in.s[c] = s[static_cast<std::size_t>(c)];
    for (int n = 0; n < 1000; ++n) gk.evolve(in, st);
    EXPECT_EQ(st.damage, 0.0);
    EXPECT_EQ(st.n_active, 0.0);
  }
}

TEST(GradyKipp, Eq18StrainInTensionIsTheIntactMatrixStrain) {
  // Eq. 18 divides the damaged stress of Eq. 14, (1 - D) s in tension, by (1 - D) E: the flaws
  // feel the strain of the intact matrix, s / E, whatever D is. The policy gets the intact
  // stress s, so with D = 0.5 an intact strain of 1.5 eps_min gives n_act = 1.5^m_p, not 3^m_p
  // (dividing s by (1 - D) again double-counts the damage). Tolerance: pow round-off.
  const GradyKipp gk{};
  DamageState<double> st = flaws(1.0e-4, 6.0, 1.0e6);
  st.damage = 0.5;
  gk.evolve(uniaxial(kYoung * 1.5e-4, 1e-12), st);
  EXPECT_NEAR(st.n_active, std::pow(1.5, 6.0), 1e-12);
}

TEST(GradyKipp, DamagedParticleBelowItsWeakestFlawDoesNotGrow) {
  // An intact strain of 0.9 eps_min activates no flaw, at D = 0 or at D = 0.5: damage must not
  // raise the strain the flaws feel above the matrix strain (hydrostatic tension too).
  const GradyKipp gk{};
  for (const double d0 : {0.0, 0.5, 0.95}) {
    DamageState<double> st = flaws(1.0e-4, 40.0, 4000.0);
    st.damage = d0;
    DamageInput<double> in = uniaxial(0.0, 1.0e-8);
    for (int k = 0; k < 3; ++k) in.s[k] = kYoung * 0.9e-4;
    for (int n = 0; n < 100; ++n) gk.evolve(in, st);
    EXPECT_EQ(st.n_active, 0.0) << "D = " << d0;
    EXPECT_EQ(st.damage, d0) << "D = " << d0;
  }
}

TEST(GradyKipp, CompressivePressureIsBorneByTheWholeParticle) {
  // Eq. 14: under compression (p > 0) only the deviator is scaled, sigma = (1 - D) s' - p I, so
  // a damaged particle feels less tension from the same intact deviator. Intact stress
  // (10, -40, -40) MPa: p = 70/3 MPa, s'_xx = 100/3 MPa. D = 0.2: sigma_max = 0.8 s'_xx - p
  // = 10/3 MPa and eps_eff = sigma_max / (0.8 E) (Eq. 18); D = 0.5: sigma_max = -20/3 MPa < 0,
  // no flaw active. Tolerance: pow round-off over m_p ln ratio ~ 4.
  const GradyKipp gk{};
  DamageInput<double> in = uniaxial(10.0e6, 1.0e-12);
  in.s[1] = in.s[2] = -40.0e6;
  const double eps_min = 5.0e-5;
  DamageState<double> st = flaws(eps_min, 6.0, 1.0e6);
  st.damage = 0.2;
  gk.evolve(in, st);
  const double eps_eff = (10.0e6 / 3.0) / (0.8 * kYoung);
  EXPECT_NEAR(st.n_active, std::pow(eps_eff / eps_min, 6.0),
              1e-12 * std::pow(eps_eff / eps_min, 6.0));
  DamageState<double> st2 = flaws(eps_min, 6.0, 1.0e6);
  st2.damage = 0.5;
  gk.evolve(in, st2);
  EXPECT_EQ(st2.n_active, 0.0);
  EXPECT_EQ(st2.damage, 0.5);
}

TEST(GradyKipp, OptionsChooseRsAndSoundSpeed) {
  // A fixed R_s and a fixed intact c_p replace the per-particle ones in Eq. 19: the first step
  // of a single-flaw particle grows D^(1/3) by 0.4 c_p dt / R_s.
  GradyKipp gk{};
  gk.params.rs = 2.0e-3;
  gk.params.intact_soundspeed = 6000.0;
  DamageState<double> st = flaws(1.0e-4, 0.0, 1.0);
  gk.evolve(uniaxial(kYoung * 2.0e-4, 1.0e-8), st);
  EXPECT_NEAR(std::cbrt(st.damage), 0.4 * 6000.0 * 1.0e-8 / 2.0e-3, 1e-15);
}

TEST(GradyKipp, SimdLanesEqualScalarPath) {
  // Random tensile and compressive states, damage and flaws. xsimd's exp/log/cbrt differ from
  // libm by a few ulp and the eigenvalue by FMA contraction (principal_test.cpp); n_act =
  // exp(m_p ln ratio) amplifies an argument error by |m_p ln ratio| <= 50 here. A relative 1e-11
  // bound covers that with margin.
  using B = test::Batch;
  constexpr std::size_t w = B::size;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  GradyKipp gk{};
  for (int rep = 0; rep < 500; ++rep) {
    alignas(64) double s[6][w], d[w], emin[w], nf[w], mp[w], vol[w], c[w];
    for (std::size_t l = 0; l < w; ++l) {
      for (int k = 0; k < 6; ++k) s[k][l] = (u(rng) - 0.3) * 3e7;
      d[l] = u(rng) < 0.3 ? 0.0 : u(rng);
      emin[l] = 1e-5 + 1e-4 * u(rng);
      nf[l] = std::floor(1.0 + 1000.0 * u(rng));
      mp[l] = nf[l] > 1.0 ? 5.0 + 40.0 * u(rng) : 0.0;
      vol[l] = 1e-9 * (0.5 + u(rng));
      c[l] = 3000.0 + 3000.0 * u(rng);
    }
    DamageInput<B> in;
    for (int k = 0; k < 6; ++k) in.s[k] = B::load_aligned(s[k]);
    in.young = B(kYoung);
    in.soundspeed = B::load_aligned(c);
    in.volume = B::load_aligned(vol);
    in.dplastic = B(0.0);
    in.dt = 1e-8;
    DamageState<B> st;
    st.damage = B::load_aligned(d);
    st.eps_min = B::load_aligned(emin);
    st.eps_max = B(0.0);
    st.n_flaws = B::load_aligned(nf);
    st.weibull_m = B::load_aligned(mp);
    st.n_active = B(0.0);
    gk.evolve(in, st);
    alignas(64) double dv[w], nv[w];
    st.damage.store_aligned(dv);
    st.n_active.store_aligned(nv);
    for (std::size_t l = 0; l < w; ++l) {
      DamageInput<double> si{};
      for (int k = 0; k < 6; ++k) si.s[k] = s[k][l];
      si.young = kYoung;
      si.soundspeed = c[l];
      si.volume = vol[l];
      si.dt = 1e-8;
      DamageState<double> ss{d[l], emin[l], 0.0, nf[l], mp[l], 0.0};
      gk.evolve(si, ss);
      ASSERT_NEAR(dv[l], ss.damage, 1e-11 * std::max(ss.damage, 1e-300));
      ASSERT_NEAR(nv[l], ss.n_active, 1e-11 * std::max(ss.n_active, 1e-300));
    }
  }
}

// The random batches of the bitwise tests below: the input of intact stresses, and the state of
// damage d and flaws (thresholds, counts, exponents).
constexpr std::size_t kW = test::Batch::size;
// Intact stresses: scale (u - 0.5) off the diagonal, scale (u - centre) on it, u in [0, 1).
DamageInput<test::Batch> batch_input(std::mt19937_64& rng, double scale, double centre, double dt) {
  using B = test::Batch;
  std::uniform_real_distribution<double> u(0.0, 1.0);
  alignas(64) double s[6][kW];
  for (std::size_t l = 0; l < kW; ++l)
    for (int k = 0; k < 6; ++k) s[k][l] = (u(rng) - (k < 3 ? centre : 0.5)) * scale;
  DamageInput<B> in;
  for (int k = 0; k < 6; ++k) in.s[k] = B::load_aligned(s[k]);
  in.young = B(kYoung);
  in.soundspeed = B(kSound);
  in.volume = B(kVolume);
  in.dplastic = B(0.0);
  in.dt = dt;
  return in;
}
// The flaws are drawn here: thresholds 1e-5-1.1e-4, 1-100 flaws, exponents 5-45.
DamageState<test::Batch> batch_state(const double (&d)[kW], std::mt19937_64& rng) {
  using B = test::Batch;
  std::uniform_real_distribution<double> u(0.0, 1.0);
  alignas(64) double emin[kW], nf[kW], mp[kW];
  for (std::size_t l = 0; l < kW; ++l) {
    emin[l] = 1e-5 + 1e-4 * u(rng);
    nf[l] = std::floor(1.0 + 100.0 * u(rng));
    mp[l] = 5.0 + 40.0 * u(rng);
  }
  return {B::load_aligned(d),  B::load_aligned(emin), B(0.0),
          B::load_aligned(nf), B::load_aligned(mp),   B(-1.0)};
}
// Bit for bit the same D and n_act in every lane.
::testing::AssertionResult same_bits(const DamageState<test::Batch>& a,
                                     const DamageState<test::Batch>& b) {
  alignas(64) double da[kW], db[kW], na[kW], nb[kW];
  a.damage.store_aligned(da), b.damage.store_aligned(db);
  a.n_active.store_aligned(na), b.n_active.store_aligned(nb);
  for (std::size_t l = 0; l < kW; ++l) {
    if (std::bit_cast<std::uint64_t>(da[l]) != std::bit_cast<std::uint64_t>(db[l]) ||
        std::bit_cast<std::uint64_t>(na[l]) != std::bit_cast<std::uint64_t>(nb[l])) {
      return ::testing::AssertionFailure() << "lane " << l << ": D " << da[l] << " / " << db[l]
                                           << ", n_act " << na[l] << " / " << nb[l];
    }
  }
  return ::testing::AssertionSuccess();
}

TEST(GradyKipp, BatchesBelowEveryThresholdKeepTheFullPathsBits) {
  // evolve() skips a batch whose Gershgorin bound puts every lane below its weakest flaw: it must
  // give the bits of the full path (evolve_full) in every lane, damaged or not, whatever the
  // state. Stresses spread over four decades around the thresholds (eps_min E ~ 0.5-5 MPa) so
  // that batches are skipped, computed in full, and decided near the bound's margin. Bound:
  // bitwise equality; the counts show both branches were taken.
  using B = test::Batch;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const GradyKipp gk{};
  int skipped = 0, full = 0;
  for (int rep = 0; rep < 4000; ++rep) {
    const double scale = std::pow(10.0, 4.0 + 4.0 * u(rng));
    const DamageInput<B> in = batch_input(rng, scale, 0.6, 1e-8);
    alignas(64) double d[kW];
    for (double& x : d) x = u(rng) < 0.5 ? 0.0 : u(rng);
    DamageState<B> a = batch_state(d, rng);
    DamageState<B> b = a;
    (gk.may_activate(in, a, gk.matrix(in, a.damage)) ? full : skipped) += 1;
    gk.evolve(in, a);
    gk.evolve_full<B, true>(in, b, gk.matrix(in, b.damage));
    ASSERT_TRUE(same_bits(a, b)) << "batch " << rep;
  }
  EXPECT_GT(skipped, 400);
  EXPECT_GT(full, 400);
}

TEST(GradyKipp, FullyDamagedBatchesKeepTheFullPathsBits) {
  // evolve_full skips Eq. 19 and BA95 Eq. 22 (three cbrt) in a batch whose lanes all have
  // D = 1, the Jacobi sweeps where bounds decide every lane (decided_by_bounds), and the sweeps
  // stop once settled (principal.hpp): every lane's D and n_act
  // must be those of the path that does all the work (kAllWork). Half the batches are fully
  // damaged; the others hold 0-7 undamaged lanes in tension (whose D grows) among failed ones.
  // Bound: bitwise equality; the counts show both kinds of batch and growing damage.
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const GradyKipp gk{};
  int failed = 0, mixed = 0, grown = 0, decided = 0, swept = 0;
  for (int rep = 0; rep < 4000; ++rep) {
    const bool all_failed = rep % 2 == 0;
    const double scale = std::pow(10.0, 5.0 + 3.0 * u(rng));
    const DamageInput<test::Batch> in = batch_input(rng, scale, 0.3, 1e-7);
    alignas(64) double d[kW];
    for (double& x : d) x = all_failed || u(rng) < 0.5 ? 1.0 : 0.5 * u(rng);
    DamageState<test::Batch> a = batch_state(d, rng);
    DamageState<test::Batch> b = a;
    DamageState<test::Batch> c = a;
    (gk.decided_by_bounds(in, c, gk.matrix(in, c.damage)) ? decided : swept) += 1;
    gk.evolve_full(in, a, gk.matrix(in, a.damage));
    gk.evolve_full<test::Batch, true>(in, b, gk.matrix(in, b.damage));
    ASSERT_TRUE(same_bits(a, b)) << "batch " << rep;
    alignas(64) double da[kW];
    a.damage.store_aligned(da);
    bool all_one = true;
    for (std::size_t l = 0; l < kW; ++l) {
      all_one = all_one && d[l] == 1.0;
      grown += da[l] > d[l] ? 1 : 0;
    }
    (all_one ? failed : mixed) += 1;
  }
  EXPECT_GT(failed, 1000);
  EXPECT_GT(mixed, 1000);
  EXPECT_GT(grown, 1000);
  EXPECT_GT(decided, 400);  // no sweep: bounds decide every lane (decided_by_bounds)
  EXPECT_GT(swept, 400);
}

TEST(GradyKipp, IdleLanesKeepTheFullPathsBits) {
  // evolve_full skips the exp and log of Eq. 17 where no lane is active, and Eq. 19 and BA95
  // Eq. 22 (three cbrt) where every lane is fully damaged or has no active flaw (settled): D and
  // n_act must be those of kAllWork. Each lane is failed (D = 1), idle (its stress scaled down
  // by 1e-6, below every threshold; D = 0 or in (0, 0.5)) or loaded (stresses at 1e5-1e8 Pa);
  // a third of the batches hold no loaded lane. Bound: bitwise equality; the counts show
  // settled batches with undamaged lanes, batches without an active lane, and batches in full.
  using B = test::Batch;
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const GradyKipp gk{};
  int settled = 0, inactive = 0, full = 0;
  for (int rep = 0; rep < 4000; ++rep) {
    DamageInput<B> in = batch_input(rng, std::pow(10.0, 5.0 + 3.0 * u(rng)), 0.3, 1e-7);
    alignas(64) double d[kW], s[6][kW];
    for (int k = 0; k < 6; ++k) in.s[k].store_aligned(s[k]);
    for (std::size_t l = 0; l < kW; ++l) {
      const double pick = u(rng);
      const bool loaded = rep % 3 != 0 && pick < 0.3;
      d[l] = pick > 0.65 ? 1.0 : (u(rng) < 0.5 ? 0.0 : 0.5 * u(rng));
      if (!loaded && d[l] < 1.0) {
        for (auto& c : s) c[l] *= 1e-6;
      }
    }
    for (int k = 0; k < 6; ++k) in.s[k] = B::load_aligned(s[k]);
    DamageState<B> a = batch_state(d, rng);
    DamageState<B> b = a;
    gk.evolve_full(in, a, gk.matrix(in, a.damage));
    gk.evolve_full<B, true>(in, b, gk.matrix(in, b.damage));
    ASSERT_TRUE(same_bits(a, b)) << "batch " << rep;
    const bool some_intact = xsimd::any(B::load_aligned(d) < 1.0);
    if (GradyKipp::settled(B::load_aligned(d), a.n_active, a.n_flaws) && some_intact) ++settled;
    if (xsimd::all(a.n_active == 0.0)) ++inactive;
    if (!GradyKipp::settled(B::load_aligned(d), a.n_active, a.n_flaws)) ++full;
  }
  EXPECT_GT(settled, 500);
  EXPECT_GT(inactive, 200);
  EXPECT_GT(full, 500);
}

}  // namespace
}  // namespace shatter::damage
