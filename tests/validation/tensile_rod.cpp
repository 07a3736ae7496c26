// The tensile rod of BA95 Sec. 5.1 through the engine: a basalt cylinder (radius 1 cm, length
// 4 cm) pulled at both ends breaks; its cracks run across the rod (perpendicular to the load); a
// six times faster pull breaks it into more pieces. Coarse resolution (1 mm points, 2 mm cells,
// 12 400 points) so that both runs take seconds.
//
// The basalt is the catalogue's (MPM paper Table 1: Tillotson EOS, linear hardening with a
// 3.5 GPa yield stress, so elastic at these loads) with Grady–Kipp damage and BA95's explicit
// N ln N flaws, built by make_material as a scene would.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "shatter/fracture/flaws.hpp"
#include "shatter/fracture/fragments.hpp"
#include "shatter/material/catalogue.hpp"
#include "shatter/mpm/simulation.hpp"
#include "support/lattice.hpp"
#include "support/sanitizers.hpp"

using namespace shatter;

namespace {

constexpr double kRho = 2700.0;   // basalt, MPM paper Table 1
constexpr double kRadius = 0.01;  // m
constexpr double kHalfLength = 0.02;
constexpr double kSpacing = 1.0e-3;

struct RodResult {
  std::size_t pieces = 0;        // fragments holding at least 2% of the rod's mass
  double failed_fraction = 0.0;  // D >= 0.9
  double min_span = 1.0;         // smallest cross-section span of those pieces / diameter
  double concentration = 0.0;    // largest share of the failed points within 3 adjacent 2 mm slabs
  double coverage = 0.0;         // largest failed fraction of one 2 mm slab across the section
  double seconds = 0.0;
};

// Pulls the rod with end caps (|x| > 1.6 cm) driven at +-strain_rate * x by a stiff body force
// and the interior started on the same homogeneous stretching v_x = strain_rate x, so the rod
// is loaded at a uniform, equilibrated strain rate (BA95: "dynamically increasing (yet
// equilibrated) longitudinal extension").
RodResult pull(double strain_rate, double t_end) {
  ParticleStore s;
  const Range r = test::add_lattice(
      s, 0, Eigen::Vector3d(-kHalfLength, -kRadius, -kRadius),
      Eigen::Vector3d(kHalfLength, kRadius, kRadius), kSpacing, kRho,
      [](const Eigen::Vector3d& x) { return x.y() * x.y() + x.z() * x.z() <= kRadius * kRadius; },
      [&](const Eigen::Vector3d& x) { return Eigen::Vector3d(strain_rate * x.x(), 0, 0); });
  // BA95's explicit N ln N flaws with the basalt Weibull parameters of Table 1.
  const DamageSpec damage_spec{
      "grady_kipp",
      {{"weibull_m", 8.5}, {"weibull_k", 3.0e39}, {"explicit_flaws", 1.0}, {"seed", 1995.0}}};
  const MaterialSpec basalt =
      MaterialCatalogue::builtin().get("basalt");  // a copy: builtin() is a temporary
  const MaterialPtr material = make_material(basalt, damage_spec);
  s.require(material->fields());
  s.require(IField::fragment);
  initialise_flaws(s, r, flaw_spec_from_params(damage_spec.params, basalt.get("young")));

  const std::size_t n = s.size();
  std::vector<double> target(n, 0.0);  // by id; 0 marks the free interior
  std::vector<char> driven(n, 0);
  for (std::size_t p = 0; p < n; ++p) {
    const double x = s.col(Field::x)[p];
    if (std::abs(x) > 0.016) {
      driven[static_cast<std::size_t>(s.col(IField::id)[p])] = 1;
      target[static_cast<std::size_t>(s.col(IField::id)[p])] = strain_rate * x;
    }
  }
  SolverConfig cfg;
  cfg.cell_size = 2.0 * kSpacing;
  cfg.viscosity = {0.2, 1.0};
  const double relax = 2.0e-7;  // s; response time of the driven caps (~2 time steps)
  cfg.body_force = [&](double, const ParticleStore& ps, double* bx, double* by, double* bz) {
    const auto ids = ps.col(IField::id);
    const auto vx = ps.col(Field::vx), vy = ps.col(Field::vy), vz = ps.col(Field::vz);
    for (std::size_t p = 0; p < ps.size(); ++p) {
      const auto id = static_cast<std::size_t>(ids[p]);
      bx[p] = driven[id] ? (target[id] - vx[p]) / relax : 0.0;
      by[p] = driven[id] ? -vy[p] / relax : 0.0;
      bz[p] = driven[id] ? -vz[p] / relax : 0.0;
    }
  };
  Simulation sim(cfg, std::move(s), {material}, 2);
  const auto start = std::chrono::steady_clock::now();
  sim.advance_to(t_end);
  RodResult out;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  ParticleStore& ps = sim.particles();
  const auto damage = ps.col(Field::damage);
  out.failed_fraction = static_cast<double>(std::count_if(damage.begin(), damage.end(),
                                                          [](double d) { return d >= 0.9; })) /
                        static_cast<double>(ps.size());
  const FragmentCatalogue cat = find_fragments(ps, FragmentSearchSpec{});
  const auto labels = ps.col(IField::fragment);
  for (const Fragment& f : cat.fragments) {
    if (f.mass < 0.02 * cat.total_mass) continue;
    ++out.pieces;
    double lo_y = 1, hi_y = -1, lo_z = 1, hi_z = -1;
    for (std::size_t p = 0; p < ps.size(); ++p) {
      if (labels[p] != f.id) continue;
      lo_y = std::min(lo_y, ps.col(Field::y)[p]);
      hi_y = std::max(hi_y, ps.col(Field::y)[p]);
      lo_z = std::min(lo_z, ps.col(Field::z)[p]);
      hi_z = std::max(hi_z, ps.col(Field::z)[p]);
    }
    out.min_span =
        std::min({out.min_span, (hi_y - lo_y) / (2 * kRadius), (hi_z - lo_z) / (2 * kRadius)});
  }
  // Where the failed material lies along the load axis, in 2 mm slabs (one cell): a crack
  // perpendicular to the load fills one or two slabs across the whole section; an oblique crack
  // across the 2 cm diameter would smear over about ten slabs.
  constexpr int kSlabs = 20;
  std::array<int, kSlabs> failed_in{}, all_in{};
  int failed_total = 0;
  for (std::size_t p = 0; p < ps.size(); ++p) {
    const int slab = std::clamp(
        static_cast<int>(std::floor((ps.col(Field::x)[p] + kHalfLength) / 0.002)), 0, kSlabs - 1);
    ++all_in[static_cast<std::size_t>(slab)];
    if (damage[p] >= 0.9) {
      ++failed_in[static_cast<std::size_t>(slab)];
      ++failed_total;
    }
  }
  for (int b = 0; b + 2 < kSlabs; ++b) {
    const auto i = static_cast<std::size_t>(b);
    const int window = failed_in[i] + failed_in[i + 1] + failed_in[i + 2];
    out.concentration =
        std::max(out.concentration, static_cast<double>(window) / std::max(failed_total, 1));
  }
  for (std::size_t i = 0; i < kSlabs; ++i)
    if (all_in[i] > 0)
      out.coverage = std::max(out.coverage, static_cast<double>(failed_in[i]) / all_in[i]);
  return out;
}

}  // namespace

TEST(TensileRod, BreaksAcrossTheLoadAndMorePiecesWhenPulledFaster) {
  // Flaws activate from eps_1 = (1/kV)^(1/m) = 7.9e-5 (4.2 MPa) and the N ln N-th flaw at 3.1e-4.
  // Slow pull 10/s: 80 us is 9 longitudinal transits of the rod (equilibrated loading) and
  // 8e-4 nominal strain. Since Eq. 18 is driven by the damaged stress (commit 8625eb3, the
  // intact stress had been divided by (1 - D) twice) cracks grow more slowly: at 60 us the rod
  // is still whole (6.8% failed), at 80 us it is in 2 pieces, at 100 us a third crack has begun
  // (seed 1995). Fast pull: six times the rate (BA95 compare a factor 6), over 60 us.
  if (test::kUnderSanitizers) {
    // Reduced form (support/sanitizers.hpp): the fast pull alone (60 us, 38 % of the test's
    // time) runs the same flaws, damage, Eq. 18 crack growth and fragment search; that it breaks
    // is checked. The slow pull's crack geometry and the rate dependence are Release checks.
    const RodResult fast = pull(60.0, 60e-6);
    std::printf("fast: pieces %zu, failed %.3f\n", fast.pieces, fast.failed_fraction);
    EXPECT_GE(fast.pieces, 2U);
    EXPECT_GT(fast.failed_fraction, 0.0);
    return;
  }
  const RodResult slow = pull(10.0, 80e-6);
  const RodResult fast = pull(60.0, 60e-6);
  for (const RodResult* r : {&slow, &fast})
    std::printf(
        "%s: pieces %zu, failed %.3f, min span %.2f, concentration %.2f, coverage %.2f "
        "(%.1f s)\n",
        r == &slow ? "slow" : "fast", r->pieces, r->failed_fraction, r->min_span, r->concentration,
        r->coverage, r->seconds);
  // It breaks: at least two pieces of >= 2% of the mass each (measured 2).
  EXPECT_GE(slow.pieces, 2U);
  // Cracks run across the load: every piece spans the rod's cross-section (a crack along the
  // axis would leave pieces spanning about half the diameter; 0.8 because the outer lattice
  // points sit half a spacing inside the surface and a piece may lose its rim; measured 0.95).
  // The failed material is a slab across the rod: one 2 mm slab failed over at least 80% of
  // the section (an oblique crack cuts each slab over ~10-20% of it; measured 0.93-1.00 over
  // flaw seeds 7, 42, 1995), holding with its neighbours more than 40% of all failed points (a
  // 45-degree crack through the 2 cm section spreads over ~10 slabs, i.e. ~30% in three;
  // measured 0.48-0.76).
  EXPECT_GE(slow.min_span, 0.8);
  EXPECT_GT(slow.concentration, 0.4);
  EXPECT_GT(slow.coverage, 0.8);
  // Rate dependence (BA95 Fig. 2): six times faster loading leaves more damage and more pieces
  // (seed 1995 after the Eq. 18 fix: 2 -> 8 pieces, 9.5% -> 46% failed; before it, 2 -> 7-8
  // pieces and 9-14% -> 54-58% over three seeds).
  EXPECT_GT(fast.failed_fraction, 2.0 * slow.failed_fraction);
  EXPECT_GT(fast.pieces, slow.pieces + 2);
  // Run time is printed, not asserted: ~3 s per run optimised, ~90 s under the Debug sanitizer
  // build, and a loaded machine would make a time bound flaky.
}
