// Steps 5-6 of the SPH step (include/shatter/sph/solver.hpp): smoothing lengths, the Verlet
// neighbour lists (with the mirror particles) and the memory re-order, then the forces pass.

#include <algorithm>
#include <cmath>
#include <numeric>

#include <tbb/parallel_for.h>

#include "shatter/core/reorder.hpp"
#include "sph/solver_impl.hpp"

namespace shatter::sph {

// Real particles; make_ghosts() extends the per-point arrays for the images (within the
// capacity once the image count stops growing: no allocation).
void SphSolver::Impl::resize(std::size_t n) {
  for (auto* v : {&h, &h_mid, &ax, &ay, &az, &heat, &mu, &kick_heat}) v->resize(n);
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

// Builds the lists with the skin (sph.skin x 2 max h) and records the positions and h they
// were built at.
// With lists = false, only the cells of a build without a skin (NeighbourSearch::bin), for a
// re-order: the same cells a full build gives, at a fraction of its cost.
void SphSolver::Impl::build_search(bool with_skin, bool lists) {
  const ParticleStore& P = s.particles_;
  const std::size_t n = P.size();
  const double hmax = exact_max(n, [&](std::size_t p) { return h[p]; });
  skin_abs = with_skin ? s.sph_.skin * 2.0 * hmax : 0.0;
  if (!lists) {
    lists_valid = false;
    if (mirrors) {
      make_ghosts(hmax);
      search.bin(ex.data(), ey.data(), ez.data(), h.data(), n + ghosts.size());
    } else {
      search.bin(P.col(Field::x).data(), P.col(Field::y).data(), P.col(Field::z).data(), h.data(),
                 n);
    }
    return;
  }
  if (mirrors) {
    make_ghosts(hmax);
    search.build(ex.data(), ey.data(), ez.data(), h.data(), n + ghosts.size(), n, skin_abs);
  } else {
    search.build(P.col(Field::x).data(), P.col(Field::y).data(), P.col(Field::z).data(), h.data(),
                 n, n, skin_abs);
  }
  const double* X[3] = {P.col(Field::x).data(), P.col(Field::y).data(), P.col(Field::z).data()};
  for (auto* v : {&xb, &yb, &zb, &hb}) v->resize(n);
  std::copy(X[0], X[0] + n, xb.begin());
  std::copy(X[1], X[1] + n, yb.begin());
  std::copy(X[2], X[2] + n, zb.begin());
  std::copy(h.begin(), h.begin() + static_cast<std::ptrdiff_t>(n), hb.begin());
  lists_valid = true;
  ++builds;
}

// Whether the lists (and images) of the last build still hold every pair within support:
// a pair outside the lists was >= h_i + h_j + skin apart at the build; since then its distance
// fell by at most |dx_i| + |dx_j| and its support grew by at most dh_i+ + dh_j+, so twice the
// largest |dx_p| + dh_p+ below the skin keeps it outside (an image moves and grows as its
// source; an image not made was >= 2 max h + skin from every real point). 1 % of the skin is
// kept for round-off. Exact maximum: any thread count decides alike.
bool SphSolver::Impl::lists_still_cover() const {
  const ParticleStore& P = s.particles_;
  const std::size_t n = P.size();
  if (!lists_valid || xb.size() != n || !(skin_abs > 0.0)) return false;
  const auto x = P.col(Field::x), y = P.col(Field::y), z = P.col(Field::z);
  const double worst = exact_max(n, [&](std::size_t p) {
    const double dx = x[p] - xb[p], dy = y[p] - yb[p], dz = z[p] - zb[p];
    return std::sqrt(dx * dx + dy * dy + dz * dz) + std::max(0.0, h[p] - hb[p]);
  });
  return 2.0 * worst <= 0.99 * skin_abs;
}

// Re-order each material group by cell (stable, so deterministic): the gather passes then
// stream through memory. The cells are those of the last bin; the lists are rebuilt for the new
// order.
void SphSolver::Impl::reorder_by_cell() {
  ParticleStore& P = s.particles_;
  const auto cells = search.cells();
  reorder_groups_by(P, order, [&](std::uint32_t p) { return cells[p]; });
  permute_switch();
  smoothing_lengths();
  build_search();
}

// Steps 5-6 of the header: a pure function of the columns (and of the step count, which picks
// the steps that re-order memory), so restore() can rebuild it bit for bit.
void SphSolver::Impl::search_and_forces(bool may_reorder) {
  ParticleStore& P = s.particles_;
  timed(kSearch, [&] {
    check_state();
    const unsigned every = s.config_.reorder_interval;
    const bool reorder = may_reorder && every > 0 && s.clock_.step % every == 0;
    if (!reorder && lists_valid && xb.size() == P.size()) {
      // Verlet lists: keep the last build's lists while they cover every pair. The passes
      // run over the lists compacted to the pairs within support (the skin's entries
      // dropped) and the lists are in index order, so the sums are those of fresh lists, bit
      // for bit (tested), and a resumed run that builds afresh continues identically.
      smoothing_lengths();
      if (lists_still_cover()) {
        if (mirrors) place_ghosts();
        return;
      }
    }
    resize(P.size());
    smoothing_lengths();
    // Before a re-order, the cells that order memory must not depend on the skin (they would
    // change the particle order and so the bits): those of a build without one, binned only
    // (the lists would be stale after the re-order).
    build_search(!reorder, !reorder);
    if (reorder) reorder_by_cell();
  });
  timed(kForces, [&] { forces(); });
}

}  // namespace shatter::sph
