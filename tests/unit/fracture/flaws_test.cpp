// Flaw initialisation: Weibull statistics of both schemes, the resolution independence of the
// MPM paper's scheme (Sec. 3.3) against Eq. 16, and independence from particle order.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <vector>

#include "shatter/fracture/counter_rng.hpp"
#include "shatter/fracture/flaws.hpp"
#include "unit/fracture/lattice.hpp"

namespace shatter {
namespace {

// A body of n particles sharing the volume `volume` (positions do not matter for flaws).
ParticleStore body(std::size_t n, double volume) {
  std::vector<test::Point> pts(n);
  for (auto& p : pts) p.volume = volume / static_cast<double>(n);
  return test::make_store(pts);
}

FlawSpec spec_of(const char* scheme, std::uint64_t seed = 7) {
  FlawSpec s;
  s.scheme = scheme;
  s.weibull_m = 8.5;
  s.weibull_k = 3.0e39;
  s.total_flaws = 1.0e9;
  s.seed = seed;
  return s;
}

constexpr double kVolume = 1.0e-4;  // m^3 (a 4.6 cm cube)

TEST(CounterRng, UniformMomentsAndNoOrderDependence) {
  // 1e6 draws: the mean of U(0,1) has sd 1/sqrt(12e6) = 2.9e-4, so 2e-3 is ~7 sigma.
  double sum = 0.0, sum2 = 0.0;
  const int n = 1000000;
  for (int i = 0; i < n; ++i) {
    const double u = counter_uniform(3, static_cast<std::uint64_t>(i), 0);
    ASSERT_GT(u, 0.0);
    ASSERT_LT(u, 1.0);
    sum += u;
    sum2 += u * u;
  }
  EXPECT_NEAR(sum / n, 0.5, 2e-3);
  EXPECT_NEAR(sum2 / n - (sum / n) * (sum / n), 1.0 / 12.0, 2e-3);
  EXPECT_EQ(counter_hash(3, 17, 2), counter_hash(3, 17, 2));
  EXPECT_NE(counter_hash(3, 17, 2), counter_hash(3, 17, 1));
  EXPECT_NE(counter_hash(3, 17, 2), counter_hash(4, 17, 2));
}

TEST(BenzAsphaugFlaws, PlacesAtLeastNlnNFlawsAndCoversEveryParticle) {
  const std::size_t n = 5000;
  ParticleStore s = body(n, kVolume);
  const FlawSpec spec = spec_of("benz_asphaug");
  initialise_flaws(s, {0, n}, spec);
  const double kv = spec.weibull_k * kVolume;
  double total = 0.0, lo = 1e300, hi = 0.0;
  for (std::size_t p = 0; p < n; ++p) {
    ASSERT_GE(s.col(Field::n_flaws)[p], 1.0);
    ASSERT_LE(s.col(Field::eps_min)[p], s.col(Field::eps_max)[p]);
    total += s.col(Field::n_flaws)[p];
    lo = std::min(lo, s.col(Field::eps_min)[p]);
    hi = std::max(hi, s.col(Field::eps_max)[p]);
  }
  EXPECT_GE(total, std::ceil(n * std::log(static_cast<double>(n))));
  // Flaw 1 has the lowest threshold of Eq. 20 and the last flaw the highest; relative 1e-13
  // allows the round-off of V summed over 5000 particle volumes (~1e-14) and of one pow.
  EXPECT_NEAR(lo, std::pow(1.0 / kv, 1.0 / 8.5), 1e-13 * lo);
  EXPECT_NEAR(hi, std::pow(total / kv, 1.0 / 8.5), 1e-13 * hi);
}

TEST(BenzAsphaugFlaws, WeakestFlawPerParticleRecoversWeibullMAndK) {
  // Flaws 1..n(e) with n(e) = kV e^m (BA95 Eq. 20) each land on a random particle, so a particle
  // has no flaw below e with probability S(e) = (1 - 1/N)^(kV e^m): ln(-ln S) = ln(kV/N) + m ln e
  // (using -ln(1 - 1/N) = 1/N to 1/(2N)). A least-squares fit over the empirical survival of
  // eps_min between S = 0.95 and 0.05 recovers m and kV. With N = 20000 the empirical quantiles
  // scatter by sqrt(S(1-S)/N) < 0.4%; over seeds the fitted m scatters by about 0.5%, so 3% on m
  // and 30% on k (ln k moves by ln(e) x dm, about 9 x 0.03) are > 5 sigma and still catch a
  // wrong exponent or a wrong volume.
  const std::size_t n = 20000;
  ParticleStore s = body(n, kVolume);
  const FlawSpec spec = spec_of("benz_asphaug", 11);
  initialise_flaws(s, {0, n}, spec);
  std::vector<double> e(s.col(Field::eps_min).begin(), s.col(Field::eps_min).end());
  std::sort(e.begin(), e.end());
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int count = 0;
  for (std::size_t i = n / 20; i <= n - n / 20; i += 50) {
    const double surv = 1.0 - (static_cast<double>(i) + 0.5) / static_cast<double>(n);
    const double x = std::log(e[i]);
    const double y = std::log(-std::log(surv));
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
    ++count;
  }
  const double slope = (count * sxy - sx * sy) / (count * sxx - sx * sx);
  const double intercept = (sy - slope * sx) / count;
  const double k_fit = std::exp(intercept) * static_cast<double>(n) / kVolume;
  EXPECT_NEAR(slope, 8.5, 0.03 * 8.5);
  EXPECT_NEAR(std::log(k_fit), std::log(3.0e39), 0.3) << "k_fit = " << k_fit;
}

TEST(ResolutionIndependentFlaws, WeakestFlawsRecoverWeibullMAndK) {
  // Sec. 3.3: the weakest flaw index is uniform on [1, 10^m], so P(eps_min <= e) = kV e^m / 10^m
  // on [eps_min,V, 10 eps_min,V]: a power law with exponent m. Maximum likelihood with unknown
  // upper end: e_hi = max sample, m = N / sum ln(e_hi / e_i) (sd m / sqrt(N) = 0.32% for
  // N = 1e5; 5 sigma = 1.6%), then k = 10^m / (V e_hi^m) (sd of ln k = ln(e_hi/10)... about
  // 9.6 x sd(m) = 0.26; 5 sigma = 1.3). e_hi / 10 = (kV)^(-1/m) itself is pinned to 1e-4
  // (the maximum of 1e5 samples misses the end by ~ e_hi / (N m) = 1e-6).
  const std::size_t n = 100000;
  ParticleStore s = body(n, kVolume);
  const FlawSpec spec = spec_of("resolution_independent", 5);
  initialise_flaws(s, {0, n}, spec);
  const auto e = s.col(Field::eps_min);
  const double e_hi = *std::max_element(e.begin(), e.end());
  double sum_log = 0.0;
  for (double v : e) sum_log += std::log(e_hi / v);
  const double m_fit = static_cast<double>(n) / sum_log;
  const double k_fit = std::pow(10.0, m_fit) / (kVolume * std::pow(e_hi, m_fit));
  const double eps_min_v = std::pow(spec.weibull_k * kVolume, -1.0 / spec.weibull_m);
  EXPECT_NEAR(m_fit, 8.5, 0.016 * 8.5);
  EXPECT_NEAR(std::log(k_fit), std::log(3.0e39), 1.3) << "k_fit = " << k_fit;
  EXPECT_NEAR(e_hi / 10.0, eps_min_v, 1e-4 * eps_min_v);
}

TEST(ResolutionIndependentFlaws, FlawCountsFollowTheBinomialNormalApproximation) {
  // n_f ~ N(n_tot/n_p, n_tot/n_p (1 - 1/n_p)): with n_p = 1e4 the mean is 1e5 and the sd 316.
  // The sample mean over 1e4 particles has sd 3.2, so 20 (6 sigma); the sample sd has relative
  // sd 1/sqrt(2 n_p) = 0.7%, so 5% is a loose but failing bound.
  const std::size_t n = 10000;
  ParticleStore s = body(n, kVolume);
  initialise_flaws(s, {0, n}, spec_of("resolution_independent"));
  const auto nf = s.col(Field::n_flaws);
  const double mean = std::accumulate(nf.begin(), nf.end(), 0.0) / n;
  double var = 0.0;
  for (double v : nf) var += (v - mean) * (v - mean);
  var /= (n - 1);
  EXPECT_NEAR(mean, 1.0e5, 20.0);
  EXPECT_NEAR(std::sqrt(var), std::sqrt(1.0e5 * (1.0 - 1.0 / n)), 0.05 * 316.2);
  // N_max sits ~ n_p below n_tot, so eps_max,p = (n_tot/kV)^(1/m) to a few 1e-5.
  const double eps_tot = std::pow(1.0e9 / (3.0e39 * kVolume), 1.0 / 8.5);
  for (std::size_t p = 0; p < n; p += 97) {
    EXPECT_NEAR(s.col(Field::eps_max)[p], eps_tot, 1e-4 * eps_tot);
    // m_p = ln(n_f) / ln(eps_max / eps_min) (after Eq. 17) reproduces n_f at eps_max.
    const double m_p = s.col(Field::weibull_m)[p];
    const double ratio = s.col(Field::eps_max)[p] / s.col(Field::eps_min)[p];
    EXPECT_NEAR(std::pow(ratio, m_p), nf[p], 1e-9 * nf[p]);
  }
}

TEST(ResolutionIndependentFlaws, MeanActivationStrainDoesNotDriftWithResolution) {
  // The same body at N, 2N, 4N and 8N particles. The mean of eps_min,p must equal
  // 10 m/(m+1) eps_min,V (Sec. 3.3): its relative sd per particle is 0.106, so at N = 4096 the
  // sample mean is within 0.17% (1 sigma); 1% is 6 sigma. The flaw-weighted mean activation
  // strain drifts only through m_p (n_f = n_tot/N changes): measured 0.5% from N to 8N, bound 2%.
  // The Benz–Asphaug scheme, by contrast, places N ln N flaws, so its mean (Eq. 16 with
  // n_tot = N ln N) grows as (8 ln 8N / ln N)^(1/m) = +29% from N to 8N: must exceed +20%.
  const std::size_t base = 4096;
  double ri_first = 0.0, ba_first = 0.0;
  for (std::size_t factor : {1, 2, 4, 8}) {
    const std::size_t n = base * factor;
    ParticleStore s = body(n, kVolume);
    const FlawSpec ri = spec_of("resolution_independent");
    initialise_flaws(s, {0, n}, ri);
    const FlawStatistics st = flaw_statistics(s, {0, n}, ri);
    EXPECT_NEAR(st.mean_eps_min, st.expected_mean_eps_min, 0.01 * st.expected_mean_eps_min)
        << "N = " << n;
    if (factor == 1) ri_first = st.mean_activation_strain;
    EXPECT_NEAR(st.mean_activation_strain, ri_first, 0.02 * ri_first) << "N = " << n;

    ParticleStore b = body(n, kVolume);
    const FlawSpec ba = spec_of("benz_asphaug");
    initialise_flaws(b, {0, n}, ba);
    const FlawStatistics sb = flaw_statistics(b, {0, n}, ba);
    if (factor == 1) ba_first = sb.eq16_activation_strain;
    if (factor == 8) {
      EXPECT_GT(sb.eq16_activation_strain, 1.2 * ba_first);
    }
  }
}

TEST(Flaws, DoNotDependOnParticleOrder) {
  // Same ids in a different storage order must give bit-identical flaws per id.
  const std::size_t n = 3000;
  std::vector<test::Point> pts(n);
  for (auto& p : pts) p.volume = kVolume / n;
  for (const char* scheme : {"benz_asphaug", "resolution_independent"}) {
    ParticleStore a = test::make_store(pts);
    ParticleStore b = test::shuffled(pts, 99);
    const FlawSpec spec = spec_of(scheme);
    initialise_flaws(a, {0, n}, spec);
    initialise_flaws(b, {0, n}, spec);
    for (std::size_t q = 0; q < n; ++q) {
      const auto id = static_cast<std::size_t>(b.col(IField::id)[q]);
      for (Field f : {Field::eps_min, Field::eps_max, Field::n_flaws, Field::weibull_m})
        ASSERT_EQ(a.col(f)[id], b.col(f)[q]) << scheme << " " << name_of(f);
    }
  }
}

TEST(Flaws, RejectBadSpecifications) {
  ParticleStore s = body(100, kVolume);
  FlawSpec spec = spec_of("resolution_independent");
  spec.total_flaws = 1.0e8;  // < 10^8.5, which Sec. 3.3 requires
  EXPECT_THROW(initialise_flaws(s, {0, 100}, spec), std::invalid_argument);
  spec = spec_of("grady");
  EXPECT_THROW(initialise_flaws(s, {0, 100}, spec), std::invalid_argument);
  spec = spec_of("benz_asphaug");
  spec.weibull_m = 0.0;
  EXPECT_THROW(initialise_flaws(s, {0, 100}, spec), std::invalid_argument);
  const FlawSpec from = flaw_spec_from_params({{"weibull_m", 9.0}, {"explicit_flaws", 1.0}}, 5e10);
  EXPECT_EQ(from.scheme, "benz_asphaug");
  EXPECT_EQ(from.weibull_m, 9.0);
  EXPECT_THROW(flaw_spec_from_params({{"explicit_flaws", 2.0}}, 5e10), std::invalid_argument);
}

}  // namespace
}  // namespace shatter

namespace shatter {
namespace {

// A half model holds n of the 2n particles and V/2 of the volume V of a body cut by its symmetry
// plane; with copies = 2 its flaws must follow the whole body's statistics (MPM paper Sec. 3.3:
// V and n_p are the body's), which a store of all 2n particles gives directly.
TEST(Flaws, HalfOfAMirroredBodyHasTheWholeBodysFlaws) {
  const std::size_t n = 4000;
  for (const char* scheme : {"benz_asphaug", "resolution_independent"}) {
    const FlawSpec spec = spec_of(scheme);
    ParticleStore half = body(n, 0.5 * kVolume);
    ParticleStore whole = body(2 * n, kVolume);
    initialise_flaws(half, {0, n}, spec, 2);
    initialise_flaws(whole, {0, 2 * n}, spec);
    const FlawStatistics h = flaw_statistics(half, {0, n}, spec, 2);
    const FlawStatistics w = flaw_statistics(whole, {0, 2 * n}, spec);
    // Sums of 4 000 and 8 000 equal volumes: round-off only.
    EXPECT_NEAR(h.volume / w.volume, 1.0, 1e-12) << scheme;
    EXPECT_NEAR(h.eps_min_volume / w.eps_min_volume, 1.0, 1e-12) << scheme;
    // Independent draws of n and 2n particles: eps_min,p has a relative spread of ~0.1 (both
    // schemes), so the means differ by a standard error of ~0.2 %; 1.5 % is 7 of them and a
    // sixth of the 2^(1/m) - 1 = 8.5 % that the half body's V gave. n_f: the resolution-
    // independent n_f spreads by 1 / sqrt(n_tot / n_p) ~ 2e-3 per particle; the Benz-Asphaug
    // mean n_f is ln(2n) = 8.99 per particle for the whole body (ln n = 8.29 for a lone half).
    EXPECT_NEAR(h.mean_eps_min / w.mean_eps_min, 1.0, 0.015) << scheme;
    EXPECT_NEAR(h.mean_flaws / w.mean_flaws, 1.0, 0.015) << scheme;
    EXPECT_NEAR(h.total_flaws / w.total_flaws, 1.0, 0.015) << scheme;
  }
  ParticleStore s = body(10, kVolume);
  EXPECT_THROW(initialise_flaws(s, {0, 10}, spec_of("benz_asphaug"), 0), std::invalid_argument);
}

}  // namespace
}  // namespace shatter
