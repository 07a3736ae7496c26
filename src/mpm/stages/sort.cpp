// App. A.2 step 1: particles sorted by grid block, and each particle's stencil at x^n.

#include <algorithm>
#include <cmath>
#include <numeric>

#include "mpm/loops.hpp"
#include "mpm/stages/stages.hpp"
#include "mpm/state.hpp"
#include "parallel/mpm/exchanges.hpp"

namespace shatter::mpm {
namespace {

// Physically re-orders each material group by block key (stable, so deterministic): the
// scatter and gather then stream through memory. The keys are computed again after the
// re-order (a function of the positions alone, so the same values, permuted) rather than
// permuted through a second key array (8 B per particle at the re-order).
template <class Shape>
void reorder(State& s) {
  ParticleStore& P = s.particles;
  const std::size_t n = P.size();
  // Only for the re-order (4 B per particle in this stage): the step retake keeps the re-order
  // rather than undoing it (retake.hpp), so nothing reads the permutation after the permute.
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0U);
  for (const Group& g : P.groups()) {
    std::stable_sort(
        order.begin() + static_cast<std::ptrdiff_t>(g.range.begin),
        order.begin() + static_cast<std::ptrdiff_t>(g.range.end),
        [&](std::uint32_t a, std::uint32_t b) { return s.owner_keys[a] < s.owner_keys[b]; });
  }
  P.permute(order, s.scratch.dx);  // through a dead buffer (Scratch)
  compute_keys<Shape>(s);
}

template <class Shape>
void sort(State& s) {
  ParticleStore& P = s.particles;
  const std::size_t n = P.size();
  s.owner_keys.resize(n);
  Scratch& sc = s.scratch;
  for (auto* v : {&sc.dx, &sc.dy, &sc.dz}) v->resize(n);
  sc.potential.resize(s.uniform_gravity() ? n : 0);  // none without gravity (Scratch)
  // uGIMP's rows are recomputed at every read (State::stencil_rows): none stored.
  constexpr bool stored = !kernels::kRecomputedRows<Shape>;
  s.stencil_w.resize(stored ? n * kernels::Stencil<Shape>::kRow : 0);
  s.stencil_off.resize(stored ? n : 0);

  compute_keys<Shape>(s);
  // The retake's copy at the end of this stage reads the velocity, stress, density and energy
  // and tests them as it copies them (Journal::save_columns): here only the other checked
  // columns (positions and sound speed), before anything uses the positions.
  const bool copy_checks = s.journal.columns_due();
  check_finite(s, copy_checks ? kCheckedByCopy : FieldSet{});

  const unsigned every = s.config.reorder_interval;
  if (every > 0 && s.clock.step % every == 0) reorder<Shape>(s);
  // The particle ids make the order inside each block canonical (SparseGrid::assign).
  const auto ids = P.col(IField::id);
  bool rebuilt = false;
  if (s.contact) {
    const auto body = P.col(IField::body);
    rebuilt = s.grid.assign(s.owner_keys, {body.data(), body.size()}, {ids.data(), ids.size()});
  } else {
    rebuilt = s.grid.assign(s.owner_keys, {}, {ids.data(), ids.size()});
  }
  if (s.dist() && (rebuilt || s.ranks.plan_version != s.ranks.decomp_version)) {
    parallel::build_halo_plan(s);
  }
  const double ih = s.inv_h();
  if constexpr (stored) {
    // Each particle's stencil at x^n, read by every transfer of the step (P2G, G2P, remap,
    // velocity gradient: kernels::StencilCache).
    const double* X[3] = {P.col(Field::x).data(), P.col(Field::y).data(), P.col(Field::z).data()};
    const double* size0 = P.col(Field::size0).data();
    const kernels::StencilCache cache = s.stencils(kernels::StencilCache::kStore);
    const bool rz = s.config.geometry == Geometry::axisymmetric;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kParticleGrain),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        if (rz) {
                          kernels::store_stencils<Shape, true>(X, size0, ih, r.begin(), r.end(),
                                                               cache);
                        } else {
                          kernels::store_stencils<Shape>(X, size0, ih, r.begin(), r.end(), cache);
                        }
                      });
  }
  if (s.driven) s.driven->scatter<Shape>(P, s.grid, s.stencil_rows<Shape>(), ih);
  // The step retake's copy of the columns the step writes, in the sorted order, in the first
  // attempt (retake.hpp, "When"); before any stage that writes them. The keys are dead from
  // here: their buffer holds the first copied column (State::owner_keys).
  // A non-finite value copied: the whole check, which names the particle (the first in the
  // sorted order) and throws if the value is one of its columns.
  if (copy_checks && !s.journal.save_columns(P, s.owner_keys)) check_finite(s);
}

// kAxisymmetric: the y stencil is the node y = 0 alone (kernels::store_stencils), in block 0.
template <class Shape, bool kAxisymmetric>
void compute_keys_in(State& s) {
  ParticleStore& P = s.particles;
  const std::size_t n = P.size();
  s.owner_keys.resize(n);
  const double ih = s.inv_h();
  const double limit = static_cast<double>(SparseGrid::kMaxBlockCoord * SparseGrid::kBlock);
  const double* X[3] = {P.col(Field::x).data(), P.col(Field::y).data(), P.col(Field::z).data()};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kParticleGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t p = r.begin(); p < r.end(); ++p) {
                        std::int64_t b[3] = {0, 0, 0};
                        for (int d = 0; d < 3; ++d) {
                          if (kAxisymmetric && d == 1) continue;
                          // The rows' first node (kernels::first_node, the one expression),
                          // so that every row lies in its owner block. Out-of-range (or NaN)
                          // positions are caught by check_finite; clamp so the key stays
                          // defined meanwhile (limit is whole: the same block as before).
                          const double f = kernels::first_node(X[d][p], ih, Shape::kShift);
                          const double c = std::isfinite(f) ? std::clamp(f, -limit, limit) : 0.0;
                          b[d] = static_cast<std::int64_t>(c) >> SparseGrid::kBlockBits;
                        }
                        s.owner_keys[p] = SparseGrid::key(b[0], b[1], b[2]);
                      }
                    });
}

}  // namespace

template <class Shape>
void compute_keys(State& s) {
  if (s.config.geometry == Geometry::axisymmetric) {
    compute_keys_in<Shape, true>(s);
  } else {
    compute_keys_in<Shape, false>(s);
  }
}

template <class Shape>
Stage sort_stage(State& s) {
  return {"sort", {kGeometry, kClock}, {all_fields(), kBlocks}, [&s] { sort<Shape>(s); }};
}

#define SHATTER_INSTANTIATE(S)              \
  template void compute_keys<S>(State & s); \
  template Stage sort_stage<S>(State & s);
SHATTER_FOR_EACH_SHAPE(SHATTER_INSTANTIATE)

}  // namespace shatter::mpm
