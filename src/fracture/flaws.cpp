// Flaw initialisation (BA95 Sec. 4.3, Eq. 20; MPM paper Sec. 3.3 after Eq. 19) and the flaw
// statistics that check it against MPM paper Eq. 16.

#include "shatter/fracture/flaws.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <vector>

#include "shatter/fracture/counter_rng.hpp"

namespace shatter {
namespace {

constexpr FieldSet kFlawFields{Field::eps_min, Field::eps_max, Field::n_flaws, Field::weibull_m,
                               Field::n_active};

void check(const FlawSpec& spec) {
  if (!(spec.weibull_m > 0.0)) throw std::invalid_argument("flaws: weibull_m must be positive");
  if (!(spec.weibull_k > 0.0)) throw std::invalid_argument("flaws: weibull_k must be positive");
  if (spec.scheme != "benz_asphaug" && spec.scheme != "resolution_independent")
    throw std::invalid_argument("flaws: unknown scheme '" + spec.scheme +
                                "' (known: benz_asphaug, resolution_independent)");
}

double body_volume(const ParticleStore& store, Range range) {
  const auto vol = store.col(Field::volume0);
  double v = 0.0;
  for (std::size_t p = range.begin; p < range.end; ++p) v += vol[p];
  if (!(v > 0.0))
    throw std::invalid_argument("flaws: body volume (sum of volume0) is not positive");
  return v;
}

// m_p = ln(n_f) / ln(eps_max / eps_min) (MPM paper, after Eq. 17). A particle with one flaw (or
// with all thresholds equal) has no spread: m_p = 0 makes Eq. 17 a step, n_act = 1 = n_f once
// eps_eff >= eps_min.
double local_m(double n_f, double eps_min, double eps_max) {
  if (n_f <= 1.0 || !(eps_max > eps_min)) return 0.0;
  return std::log(n_f) / std::log(eps_max / eps_min);
}

// BA95 Sec. 4.3: flaw j = 1, 2, ... with threshold (j / kV)^(1/m) (Eq. 20) goes to a uniformly
// random particle, until N ln N flaws are placed and every particle holds at least one. The
// particle is drawn by rank among the sorted ids, so the draw is independent of storage order.
// With copies > 1 the body has copies x n particles, N = copies n: ranks [0, n) are the stored
// particles, the others their mirror images, which take part in the draw but are not stored.
void benz_asphaug(ParticleStore& store, Range range, const FlawSpec& spec, double kv,
                  std::size_t copies) {
  const std::size_t n = range.size();
  const std::size_t n_body = copies * n;
  const auto ids = store.col(IField::id);
  std::vector<std::uint32_t> by_id(n);
  std::iota(by_id.begin(), by_id.end(), 0U);
  std::sort(by_id.begin(), by_id.end(), [&](std::uint32_t a, std::uint32_t b) {
    return ids[range.begin + a] < ids[range.begin + b];
  });
  std::vector<std::uint64_t> first(n_body, 0), last(n_body, 0), count(n_body, 0);
  const double nd = static_cast<double>(n_body);
  const auto target = static_cast<std::uint64_t>(std::ceil(nd * std::log(std::max(nd, 1.0))));
  std::size_t covered = 0;
  for (std::uint64_t j = 1; j <= target || covered < n_body; ++j) {
    const double u = counter_uniform(spec.seed, j, 0);
    const auto rank = std::min(static_cast<std::size_t>(u * nd), n_body - 1);
    const std::size_t q = rank < n ? by_id[rank] : rank;
    if (count[q] == 0) {
      first[q] = j;
      ++covered;
    }
    last[q] = j;
    ++count[q];
  }
  auto eps_min = store.col(Field::eps_min);
  auto eps_max = store.col(Field::eps_max);
  auto n_flaws = store.col(Field::n_flaws);
  auto m_p = store.col(Field::weibull_m);
  const double inv_m = 1.0 / spec.weibull_m;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t p = range.begin + i;
    eps_min[p] = std::pow(static_cast<double>(first[i]) / kv, inv_m);  // BA95 Eq. 20
    eps_max[p] = std::pow(static_cast<double>(last[i]) / kv, inv_m);
    n_flaws[p] = static_cast<double>(count[i]);
    m_p[p] = local_m(n_flaws[p], eps_min[p], eps_max[p]);
  }
}

// MPM paper Sec. 3.3, the three bullets after Eq. 19, with three independent uniforms per
// particle id (streams 0..3). n_p is that of the whole body, copies x the stored particles.
// In r-z (spec.rings) n_p is replaced per point by V / V_p with V_p = A^(3/2), the volume of the
// 3-D point of the ring's cross-section A = volume0 / (2 pi x): the body's flaws spread over the
// 3-D points it would hold, and the ring takes the draw of one of them (its weakest flaw, n_f and
// N_max as that point's), so that its Grady-Kipp damage is that point's (R_s likewise,
// kernels/constitutive/composed_kernel.hpp).
void resolution_independent(ParticleStore& store, Range range, const FlawSpec& spec, double kv,
                            std::size_t copies) {
  const double m = spec.weibull_m;
  const double n_tot = spec.total_flaws;
  const double ten_m = std::pow(10.0, m);
  if (!(n_tot > ten_m))
    throw std::invalid_argument(
        "flaws: resolution_independent needs total_flaws > 10^m (MPM paper Sec. 3.3; Table 3 "
        "note b uses 1e19 for m = 17.2)");
  const double n_p = static_cast<double>(copies * range.size());
  if (n_tot < n_p) throw std::invalid_argument("flaws: total_flaws is below the particle count");
  // Binomial(n_tot, 1/n_p) -> normal with mean n_tot/n_p and variance n_tot/n_p (1 - 1/n_p).
  double mean_nf = n_tot / n_p;
  double sd_nf = std::sqrt(mean_nf * (1.0 - 1.0 / n_p));
  double log_q = std::log1p(-1.0 / n_p);  // ln(1 - 1/n_p); -inf for a single particle
  const double inv_m = 1.0 / m;
  const double body_v = kv / spec.weibull_k;
  const auto vol0 = store.col(Field::volume0);
  const auto xs = store.col(Field::x);
  const auto ids = store.col(IField::id);
  auto eps_min = store.col(Field::eps_min);
  auto eps_max = store.col(Field::eps_max);
  auto n_flaws = store.col(Field::n_flaws);
  auto m_p = store.col(Field::weibull_m);
  for (std::size_t p = range.begin; p < range.end; ++p) {
    const auto key = static_cast<std::uint64_t>(ids[p]);
    if (spec.rings) {
      const double a = vol0[p] / (2.0 * std::numbers::pi * xs[p]);  // the ring's cross-section
      const double w = std::min(1.0, a * std::sqrt(a) / body_v);    // 1 / n_p of a 3-D lattice
      mean_nf = n_tot * w;
      sd_nf = std::sqrt(mean_nf * (1.0 - w));
      log_q = std::log1p(-w);
    }
    // Bullet 2: the index of the weakest flaw is uniform on [1, 10^m], so eps_min,p spans one
    // order of magnitude above eps_min,V = (kV)^(-1/m) and averages 10 m/(m+1) eps_min,V.
    const double n_min = 1.0 + counter_uniform(spec.seed, key, 0) * (ten_m - 1.0);
    // Bullet 3: n_f from the normal approximation (Box–Muller on streams 1 and 2).
    const double z = std::sqrt(-2.0 * std::log(counter_uniform(spec.seed, key, 1))) *
                     std::cos(2.0 * std::numbers::pi * counter_uniform(spec.seed, key, 2));
    const double nf = std::max(1.0, std::round(mean_nf + sd_nf * z));
    // Bullet 4: N_max = n_tot - ln(x) / ln(1 - 1/n_p) from F(N) ~ (1 - 1/n_p)^(n_tot - N).
    const double x = counter_uniform(spec.seed, key, 3);
    const double n_max_raw = std::isfinite(log_q) ? n_tot - std::log(x) / log_q : n_tot;
    const double n_max = std::clamp(n_max_raw, n_min, n_tot);
    eps_min[p] = std::pow(n_min / kv, inv_m);
    eps_max[p] = nf > 1.0 ? std::pow(n_max / kv, inv_m) : eps_min[p];
    n_flaws[p] = nf;
    m_p[p] = local_m(nf, eps_min[p], eps_max[p]);
  }
}

}  // namespace

void initialise_flaws(ParticleStore& store, Range range, const FlawSpec& spec, std::size_t copies) {
  check(spec);
  if (copies == 0) throw std::invalid_argument("flaws: copies must be at least 1");
  if (range.empty()) return;
  if (!store.has(IField::id)) throw std::logic_error("flaws: the particle store has no id column");
  if (spec.rings && spec.scheme != "resolution_independent")
    throw std::invalid_argument(
        "flaws: explicit flaws (benz_asphaug) are not drawn for r-z rings; use the "
        "resolution-independent scheme (explicit_flaws = 0)");
  store.require(kFlawFields);
  // V of Eqs. 15-20 is the whole body's: a half model holds half of it.
  const double kv = spec.weibull_k * static_cast<double>(copies) * body_volume(store, range);
  if (spec.scheme == "benz_asphaug")
    benz_asphaug(store, range, spec, kv, copies);
  else
    resolution_independent(store, range, spec, kv, copies);
  auto n_active = store.col(Field::n_active);
  std::fill(n_active.begin() + static_cast<std::ptrdiff_t>(range.begin),
            n_active.begin() + static_cast<std::ptrdiff_t>(range.end), 0.0);
}

FlawStatistics flaw_statistics(const ParticleStore& store, Range range, const FlawSpec& spec,
                               std::size_t copies) {
  check(spec);
  if (copies == 0) throw std::invalid_argument("flaws: copies must be at least 1");
  FlawStatistics s;
  if (range.empty()) return s;
  const double m = spec.weibull_m;
  s.particles = range.size();
  s.volume = static_cast<double>(copies) * body_volume(store, range);
  const double kv = spec.weibull_k * s.volume;
  const auto eps_min = store.col(Field::eps_min);
  const auto eps_max = store.col(Field::eps_max);
  const auto n_flaws = store.col(Field::n_flaws);
  const auto m_p = store.col(Field::weibull_m);
  double sum_eps_min = 0.0, weighted = 0.0, sum_m = 0.0;
  std::size_t n_multi = 0;
  for (std::size_t p = range.begin; p < range.end; ++p) {
    const double nf = n_flaws[p];
    s.total_flaws += nf;
    sum_eps_min += eps_min[p];
    // Mean of a per-particle threshold law with (eps/eps_min)^m_p flaws below eps, capped at n_f
    // at eps_max: E = eps_max - integral of the CDF = m_p/(m_p+1) eps_max + eps_min/(n_f(m_p+1)).
    const double mean_p = (m_p[p] * eps_max[p] + eps_min[p] / nf) / (m_p[p] + 1.0);
    weighted += nf * mean_p;
    if (nf > 1.0) {
      sum_m += m_p[p];
      ++n_multi;
    }
  }
  const double np = static_cast<double>(s.particles);
  s.mean_flaws = s.total_flaws / np;
  // The mirror images hold as many flaws again, statistically.
  s.total_flaws *= static_cast<double>(copies);
  s.mean_local_m = n_multi > 0 ? sum_m / static_cast<double>(n_multi) : 0.0;
  s.eps_min_volume = std::pow(kv, -1.0 / m);
  s.mean_eps_min = sum_eps_min / np;
  s.expected_mean_eps_min = 10.0 * m / (m + 1.0) * s.eps_min_volume;
  s.mean_activation_strain = weighted / s.total_flaws;
  s.eq16_activation_strain = m / (m + 1.0) * std::pow(s.total_flaws / kv, 1.0 / m);  // Eq. 16
  return s;
}

FlawSpec flaw_spec_from_params(const std::map<std::string, double>& params, double young) {
  FlawSpec spec;
  spec.young = young;
  const auto get = [&](const char* key, double fallback) {
    const auto it = params.find(key);
    return it == params.end() ? fallback : it->second;
  };
  spec.weibull_m = get("weibull_m", spec.weibull_m);
  spec.weibull_k = get("weibull_k", spec.weibull_k);
  spec.total_flaws = get("total_flaws", spec.total_flaws);
  const double explicit_flaws = get("explicit_flaws", 0.0);
  if (explicit_flaws != 0.0 && explicit_flaws != 1.0)
    throw std::invalid_argument("damage: explicit_flaws must be 0 or 1");
  spec.scheme = explicit_flaws == 1.0 ? "benz_asphaug" : "resolution_independent";
  const double seed = get("seed", static_cast<double>(spec.seed));
  if (!(seed >= 0.0) || seed != std::floor(seed) || seed > 9.0e15)
    throw std::invalid_argument("damage: seed must be a non-negative integer");
  spec.seed = static_cast<std::uint64_t>(seed);
  check(spec);
  return spec;
}

}  // namespace shatter
