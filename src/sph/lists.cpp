// Steps 5-6 of the SPH step (include/shatter/sph/solver.hpp): smoothing lengths, the Verlet
// neighbour lists (with the mirror particles) and the memory re-order, then the forces pass.

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include <tbb/parallel_for.h>

#include "shatter/core/reorder.hpp"
#include "sph/solver_impl.hpp"

namespace shatter::sph {

// Real particles; make_ghosts() extends the per-point arrays for the images (within the
// capacity once the image count stops growing: no allocation).
void SphSolver::Impl::resize(std::size_t n) {
  for (auto* v : {&h, &h_mid, &ax, &ay, &az, &heat}) v->resize(n);
  for (auto& v : a_stress) v.resize(n);
}

// h = h_factor (m / rho)^{1/3} (see the header: dh/dt = h div v / 3 integrated exactly).
void SphSolver::Impl::smoothing_lengths() {
  const ParticleStore& P = s.particles_;
  const double* m = P.col(Field::mass).data();
  const double* rho = P.col(Field::rho).data();
  const double f = s.sph_.h_factor;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, P.size(), kGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t p = r.begin(); p < r.end(); ++p) {
                        h[p] = f * std::cbrt(m[p] / rho[p]);
                      }
                    });
}

// Each real particle's half of the Verlet skin (a pair (i, j) is listed within
// h_i + h_j + s_i + s_j), at least sph.skin x max h (so sph.skin x 2 max h for a pair, as the
// scene key says) and, for a fast particle, kSkinSteps steps of its own travel at the last
// step's dt, up to kSkinCap times that floor. With one skin for all, the fastest particles set
// how long every list lasts: in the laboratory impact the projectile and the shocked contact
// (~3 km/s) forced a build every 2.6 steps, a third of the run (docs/performance.md, SPH round
// 5). A larger skin for those few particles only lengthens their lists, not everyone's (the
// search sizes its cells for all but the widest 1 %: NeighbourSearch, split_). Any skin gives
// the same compacted lists and so the same bits. sph.skin = 0 keeps no skin at all (a build
// every step). 16 steps and 6x were the best of a sweep of the laboratory impact when the
// largest skin set every point's cell edge (42 builds in 110 steps -> 12); with the cells sized
// for the many, 24 steps and 12x: 22 builds in its first 221 steps -> 13, 3 % fewer CPU
// samples (docs/performance.md, session 22: SPH). Returns the largest s_p.
namespace {
constexpr double kSkinSteps = 24.0;
constexpr double kSkinCap = 12.0;

// v >= 0 as the largest float not above it.
float round_down(double v) {
  const auto f = static_cast<float>(v);
  return static_cast<double>(f) > v ? std::nextafter(f, 0.0f) : f;
}
}  // namespace

double SphSolver::Impl::particle_skins(double hmax, bool with_skin) {
  const ParticleStore& P = s.particles_;
  const std::size_t n = P.size();
  const double least = with_skin ? s.sph_.skin * hmax : 0.0;
  const double travel = kSkinSteps * s.clock_.dt_prev;
  const double* V[3] = {P.col(Field::vx).data(), P.col(Field::vy).data(), P.col(Field::vz).data()};
  skin.resize(n);
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, n, kGrain), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t p = r.begin(); p < r.end(); ++p) {
          const double v = std::sqrt(V[0][p] * V[0][p] + V[1][p] * V[1][p] + V[2][p] * V[2][p]);
          skin[p] = round_down(std::min(kSkinCap * least, std::max(least, travel * v)));
        }
      });
  return exact_max(n, [&](std::size_t p) { return static_cast<double>(skin[p]); });
}

// The viscous weights' storage lent to the search for its sort buffers (NeighbourSearch::lend)
// for a build or bin over `points` points: it is free in the search stage (the rates pass has
// read the weights, the forces pass rewrites them), and mostly larger (~27 doubles per point in
// the benchmark's cube against 4). Grown (its content dropped) where it is not.
void SphSolver::Impl::lend_weights(std::size_t points) {
  const std::size_t need = NeighbourSearch::sort_doubles(points);
  pair_w.grow_discarding(need);
  search.lend(pair_w);
}

// Builds the lists with the particles' skins (particle_skins) and records the positions, h and
// skins they were built at. With lists = false, only the cells of a build without a skin
// (NeighbourSearch::bin), for a re-order: the same cells a full build gives, at a fraction of
// its cost.
void SphSolver::Impl::build_search(bool with_skin, bool lists) {
  const ParticleStore& P = s.particles_;
  const std::size_t n = P.size();
  const double hmax = exact_max(n, [&](std::size_t p) { return h[p]; });
  if (!lists) {
    skin_abs = 0.0;
    lists_valid = false;
    if (mirrors) {
      make_ghosts(hmax);
      lend_weights(n + ghosts.size());
      search.bin(ex.data(), ey.data(), ez.data(), h.data(), n + ghosts.size());
    } else {
      lend_weights(n);
      search.bin(P.col(Field::x).data(), P.col(Field::y).data(), P.col(Field::z).data(), h.data(),
                 n);
    }
    return;
  }
  // skin_abs: the largest pair skin, 2 max s_p (the images within 2 max h + skin_abs of a face
  // are made: an image not made is then farther than h_i + h_j + s_i + s_j from every point).
  skin_abs = 2.0 * particle_skins(hmax, with_skin);
  if (mirrors) make_ghosts(hmax);
  // The search's reach per point, h + s (h_mid is free here: the rates pass rewrites it), the
  // images taking their sources'; the search then lists pairs within (h_i + s_i) + (h_j + s_j).
  const std::size_t m = n + (mirrors ? ghosts.size() : 0);
  lend_weights(m);
  h_mid.resize(m);
  for (std::size_t p = 0; p < n; ++p) h_mid[p] = h[p] + skin[p];
  for (std::size_t k = 0; k < m - n; ++k) h_mid[n + k] = h_mid[ghosts[k].src];
  if (mirrors) {
    search.build(ex.data(), ey.data(), ez.data(), h_mid.data(), m, n, 0.0);
  } else {
    search.build(P.col(Field::x).data(), P.col(Field::y).data(), P.col(Field::z).data(),
                 h_mid.data(), n, n, 0.0);
  }
  const double* X[3] = {P.col(Field::x).data(), P.col(Field::y).data(), P.col(Field::z).data()};
  for (auto* v : {&xb, &yb, &zb, &hb}) v->resize(n);
  const auto nearest = [](double v) { return static_cast<float>(v); };
  std::transform(X[0], X[0] + n, xb.begin(), nearest);
  std::transform(X[1], X[1] + n, yb.begin(), nearest);
  std::transform(X[2], X[2] + n, zb.begin(), nearest);
  std::transform(h.begin(), h.begin() + static_cast<std::ptrdiff_t>(n), hb.begin(), round_down);
  lists_valid = true;
  lists_sorted = true;
  ++builds;
}

// Whether the lists (and images) of the last build still hold every pair within support:
// a pair outside the lists was >= h_i + h_j + s_i + s_j apart at the build; since then its
// distance fell by at most |dx_i| + |dx_j| and its support grew by at most dh_i+ + dh_j+, so
// |dx_p| + dh_p+ below s_p for every p keeps it outside (an image moves and grows as its
// source; an image not made was >= 2 max h + 2 max s from every real point). 1 % of each skin
// is kept for round-off. Exact maximum: any thread count decides alike. The build's positions
// are held rounded to float, each within 2^-24 of its magnitude (FLT_MIN absolute where
// subnormal): |dx_p| is at most the distance to the rounded position plus those bounds, taken
// here as 2^-23 of each magnitude (twice the bound) plus FLT_MIN per axis; h at the build is
// rounded down, which only overstates the growth.
bool SphSolver::Impl::lists_still_cover() const {
  const ParticleStore& P = s.particles_;
  const std::size_t n = P.size();
  if (!lists_valid || xb.size() != n || skin.size() != n || !(skin_abs > 0.0)) return false;
  const auto x = P.col(Field::x), y = P.col(Field::y), z = P.col(Field::z);
  const double kFloatMin = 3.0 * static_cast<double>(std::numeric_limits<float>::min());
  // Each term <= 0 where the particle is still covered; exact_max starts from 0.
  const double worst = exact_max(n, [&](std::size_t p) {
    const double xf = xb[p], yf = yb[p], zf = zb[p];
    const double dx = x[p] - xf, dy = y[p] - yf, dz = z[p] - zf;
    const double rounding = 0x1p-23 * (std::abs(xf) + std::abs(yf) + std::abs(zf)) + kFloatMin;
    const double used = std::sqrt(dx * dx + dy * dy + dz * dz) + rounding +
                        std::max(0.0, h[p] - static_cast<double>(hb[p]));
    return used - 0.99 * static_cast<double>(skin[p]);
  });
  return worst <= 0.0;
}

// Re-order each material group by cell (stable, so deterministic): the gather passes then
// stream through memory. The cells are those of the last bin. With keep_lists (the last build's
// lists still cover every pair within support), the lists are carried through the permutation
// (permute_lists); otherwise they are rebuilt for the new order.
void SphSolver::Impl::reorder_by_cell(bool keep_lists) {
  ParticleStore& P = s.particles_;
  const auto cells = search.cells();
  reorder_groups_by(P, order, [&](std::uint32_t p) { return cells[p]; });
  permute_switch();
  smoothing_lengths();
  if (keep_lists) {
    permute_lists();
  } else {
    build_search();
  }
}

// The last build's lists, images and build state carried through the re-order's permutation
// (new particle k is old particle order[k]) instead of a build, which took ~10 % of the
// laboratory impact (docs/performance.md, SPH round 5). The passes see exactly what a fresh
// build gives: the compacted lists are the pairs within support in ascending index order, and
// they do not depend on the skin or on the build's positions as long as the lists cover every
// pair within support (lists_still_cover, checked before). The images kept are those of the
// last build (kept_ghosts, saved before the bin made its own), renumbered and put in the order
// make_ghosts gives them (by source, then by the sides in its loop order: 0, -1, +1 on x, then
// y, then z), so every image within support has the same rank among the images as in a fresh
// build and the lists, sorted again, sum the same terms in the same order: the same bits. The
// per-particle state of the build (positions, h and skins at the build) is permuted with the
// particles, so the next build comes when it would have come without the re-order.
void SphSolver::Impl::permute_lists() {
  const std::size_t n = s.particles_.size();
  ghosts.swap(kept_ghosts);
  const std::size_t g = ghosts.size();
  renumber.resize(n + g);
  for (std::size_t k = 0; k < n; ++k) renumber[order[k]] = static_cast<std::uint32_t>(k);
  // Build state: new k from old order[k] (heat as the scratch copy, as permute_switch does: the
  // forces pass after the re-order rewrites it).
  for (auto* v : {&xb, &yb, &zb, &hb, &skin}) {
    for (std::size_t k = 0; k < n; ++k) heat[k] = (*v)[order[k]];  // float -> double: exact
    std::copy(heat.begin(), heat.begin() + static_cast<std::ptrdiff_t>(n), v->begin());
  }
  // The images: sources renumbered, then sorted by (source, sides in make_ghosts' order); the
  // old image n + k becomes n + its rank. kept_ghosts (the bin's images, no longer needed)
  // takes the sorted copy.
  const auto rank = [](std::int8_t side) { return side == 0 ? 0 : (side < 0 ? 1 : 2); };
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(g);
  for (std::size_t k = 0; k < g; ++k) {
    const Mirror& m = ghosts[k];
    const auto sides = 9 * rank(m.side[0]) + 3 * rank(m.side[1]) + rank(m.side[2]);
    keyed[k] = {(std::uint64_t{renumber[m.src]} << 8) | static_cast<std::uint64_t>(sides),
                static_cast<std::uint32_t>(k)};
  }
  std::sort(keyed.begin(), keyed.end());
  kept_ghosts.resize(g);
  for (std::size_t r = 0; r < g; ++r) {
    const std::uint32_t k = keyed[r].second;
    kept_ghosts[r] = {renumber[ghosts[k].src], ghosts[k].side};
    renumber[n + k] = static_cast<std::uint32_t>(n + r);
  }
  ghosts.swap(kept_ghosts);
  // The per-point arrays for these images (make_ghosts' sizes), their positions and h.
  if (mirrors) {
    size_ghost_columns(n + g);
    place_ghosts();
  }
  // The lists as the last forces pass left them: the pairs within support first (active_count,
  // permuted with the particles), the skin's entries after them. Only those first ones are
  // sorted again, which is all compact_lists asks for (the skin's are sorted in there, by
  // insertion, only when they come within support).
  for (std::size_t k = 0; k < n; ++k) heat[k] = active_count[order[k]];  // uint32 -> double: exact
  std::copy(heat.begin(), heat.begin() + static_cast<std::ptrdiff_t>(n), active_count.begin());
  search.permute(order, renumber, active_count);
  lists_sorted = false;
}

// Steps 5-6 of the header: a pure function of the columns (and of the step count, which picks
// the steps that re-order memory), so restore() can rebuild it bit for bit.
void SphSolver::Impl::search_and_forces(bool may_reorder) {
  ParticleStore& P = s.particles_;
  timed(kSearch, [&] {
    check_state();
    const unsigned every = s.config_.reorder_interval;
    const bool reorder = may_reorder && every > 0 && s.clock_.step % every == 0;
    bool cover = false;
    if (lists_valid && xb.size() == P.size()) {
      // Verlet lists: keep the last build's lists while they cover every pair. The passes
      // run over the lists compacted to the pairs within support (the skin's entries
      // dropped) and the lists are in index order, so the sums are those of fresh lists, bit
      // for bit (tested), and a resumed run that builds afresh continues identically.
      smoothing_lengths();
      cover = lists_still_cover();
      if (cover && !reorder) {
        if (mirrors) place_ghosts();
        return;
      }
    }
    resize(P.size());
    smoothing_lengths();
    // Before a re-order, the cells that order memory must not depend on the skin (they would
    // change the particle order and so the bits): those of a build without one, binned only.
    // Lists that still cover are then carried through the re-order (the bin keeps them, and
    // the last build's images and largest skin are put aside for them); otherwise they are
    // built for the new order.
    const double kept_skin = skin_abs;
    if (reorder && cover) ghosts.swap(kept_ghosts);
    build_search(!reorder, !reorder);
    if (reorder) reorder_by_cell(cover);
    if (reorder && cover) {
      skin_abs = kept_skin;
      lists_valid = true;
    }
  });
  timed(kForces, [&] { forces(); });
}

}  // namespace shatter::sph
