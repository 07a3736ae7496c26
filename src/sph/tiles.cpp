// The pair passes' tiles and the forces pass (step 6, BA95 Eq. 17 with Monaghan's viscosity) in
// the symmetric form (kernels/sph/pairs.hpp): each pair within support evaluated once, from its
// lower particle, its share added to the upper particle's sums. The tiles are the chunks of
// kPairGrain particles (a function of the particle order only). A tile writes the sums of its
// own particles and of the upper neighbours of its pairs (up to its reach: a chunk); the tiles are
// coloured so that no two of a colour have a target in common, and the colours run one after
// the other, each colour's tiles in parallel (over_tiles). So every particle's sum adds its
// shares in the order (colour of the writing tile, the tile's particle order), which the lists
// alone fix: the bits do not depend on the thread count. (Before session 23 every pair was
// evaluated from both sides, each particle gathering its own sums: docs/performance.md.)

#include <algorithm>
#include <atomic>
#include <bit>

#include <tbb/parallel_for.h>

#include "sph/pairs.hpp"
#include "sph/solver_impl.hpp"

namespace shatter::sph {

namespace {

// Room for n entries in v, grown by an eighth when short (as the search's list buffers). Growing
// to the exact count re-allocated (and copied) at nearly every list build and every step of a
// compressing flow: in the laboratory impact that copy and its page faults were 15 % of the
// run (docs/performance.md, SPH round 5). The content is not kept across the growth (it is
// rewritten before it is read), so the old array is dropped before the new one is made.
template <class V>
void make_room(V& v, std::size_t n) {
  if (v.capacity() < n) {
    const std::size_t cap = std::max(n, v.capacity() + v.capacity() / 8);
    V().swap(v);
    v.reserve(cap);
  }
  v.resize(n);
}

}  // namespace

// Chunk c's particles' lists partitioned (compact_lists), their upper halves found, and the
// highest chunk it writes (its own, or that of its highest real upper neighbour) in chunk_reach[c].
// Returns the groups of its viscous weights' masks.
std::size_t SphSolver::Impl::compact_chunk(std::size_t c, const ks::PairInputs& in,
                                           std::vector<std::uint32_t>& scratch) {
  const std::size_t n = s.particles_.size();
  const std::size_t end = std::min(n, (c + 1) * kPairGrain);
  auto top = static_cast<std::uint32_t>(c);
  std::size_t masks = 0;
  for (std::size_t i = c * kPairGrain; i < end; ++i) {
    const std::size_t count = search.count(i);
    if (scratch.size() < count + 8) scratch.resize(count + 8);
    const std::size_t sorted = lists_sorted ? count : active_count[i];
    const std::uint32_t* list = search.rearrange(i);
    active_count[i] = static_cast<std::uint32_t>(
        ks::partition_within_support(in, search.rearrange(i), count, sorted, i, scratch.data()));
    upper_at[i] = static_cast<std::uint32_t>(ks::upper_half(list, active_count[i], i));
    masks += groups(active_count[i] - upper_at[i]);
    // Ascending, images (>= n) last: the highest real entry.
    std::size_t k = active_count[i];
    while (k > upper_at[i] && list[k - 1] >= n) --k;
    if (k > upper_at[i]) top = std::max(top, static_cast<std::uint32_t>(list[k - 1] / kPairGrain));
  }
  chunk_reach[c] = top;
  return masks;
}

// Each list re-arranged so that its pairs within support come first, in ascending index order
// (a Verlet list's skin entries after them), which the forces pass and the next step's rates
// pass use: it runs at these same positions and h. The viscous weights' masks are kept for the
// upper halves of those (chunk_mask: where each chunk's start). Then the tiles coloured.
void SphSolver::Impl::compact_lists(const ks::PairInputs& in) {
  const std::size_t n = s.particles_.size();
  const std::size_t chunks = (n + kPairGrain - 1) / kPairGrain;
  active_count.resize(n);
  upper_at.resize(n);
  chunk_mask.resize(chunks + 1);
  chunk_reach.resize(chunks);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks, 1),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      std::vector<std::uint32_t>& scratch = rest.local();
                      for (std::size_t c = r.begin(); c < r.end(); ++c) {
                        chunk_mask[c + 1] = compact_chunk(c, in, scratch);
                      }
                    });
  lists_sorted = false;
  chunk_mask[0] = 0;
  for (std::size_t c = 0; c < chunks; ++c) chunk_mask[c + 1] += chunk_mask[c];
  make_room(pair_mask, chunk_mask[chunks]);
  colour_tiles();
}

// The tiles: runs of tile_chunks consecutive chunks, tile_chunks the median over chunks of how
// far (in chunks) above itself a chunk writes, plus one: so a tile mostly writes only itself and
// the next, and runs its chunks in order over a window of neighbours that stays in cache (tiles
// of one chunk, each colour's spread over the whole store, made both passes 1.3x slower than in
// chunk order: measured, session 23). Greedy colouring in tile order: each tile takes the lowest
// colour that no earlier tile with a target in common has (busy[t]: the colours of the tiles
// writing tile t, one bit each); in the cube two colours. Then tile_order lists the tiles by
// colour, then index; colour_start where each colour begins.
void SphSolver::Impl::colour_tiles() {
  const std::size_t chunks = chunk_reach.size();
  std::vector<std::uint32_t> span(chunks);
  for (std::size_t c = 0; c < chunks; ++c) span[c] = chunk_reach[c] - static_cast<std::uint32_t>(c);
  std::nth_element(span.begin(), span.begin() + static_cast<std::ptrdiff_t>(chunks / 2),
                   span.end());
  tile_chunks = chunks > 0 ? span[chunks / 2] + 1 : 1;
  const std::size_t tiles = (chunks + tile_chunks - 1) / tile_chunks;
  busy.resize(tiles);
  for (auto& b : busy) b.clear();
  std::vector<std::uint32_t> colour(tiles);
  std::vector<std::uint64_t> taken;
  std::uint32_t colours = 0;
  for (std::size_t u = 0; u < tiles; ++u) {
    // The tiles u writes: u .. last (an interval that holds every one).
    std::size_t last = u;
    for (std::size_t c = u * tile_chunks; c < std::min(chunks, (u + 1) * tile_chunks); ++c) {
      last = std::max(last, chunk_reach[c] / tile_chunks);
    }
    taken.clear();
    for (std::size_t t = u; t <= last; ++t) {
      if (taken.size() < busy[t].size()) taken.resize(busy[t].size(), 0);
      for (std::size_t w = 0; w < busy[t].size(); ++w) taken[w] |= busy[t][w];
    }
    std::size_t w = 0;
    while (w < taken.size() && taken[w] == ~std::uint64_t{0}) ++w;
    const std::size_t k = 64 * w + (w < taken.size() ? std::countr_one(taken[w]) : 0);
    colour[u] = static_cast<std::uint32_t>(k);
    colours = std::max(colours, colour[u] + 1);
    for (std::size_t t = u; t <= last; ++t) {
      if (busy[t].size() <= k / 64) busy[t].resize(k / 64 + 1, 0);
      busy[t][k / 64] |= std::uint64_t{1} << (k % 64);
    }
  }
  colour_start.assign(colours + 1, 0);
  for (const std::uint32_t k : colour) ++colour_start[k + 1];
  for (std::uint32_t k = 0; k < colours; ++k) colour_start[k + 1] += colour_start[k];
  tile_order.resize(tiles);
  std::vector<std::uint32_t> at(colour_start.begin(), colour_start.end() - 1);
  for (std::size_t u = 0; u < tiles; ++u)
    tile_order[at[colour[u]]++] = static_cast<std::uint32_t>(u);
}

// A new layout of pair_w after a forces pass in which chunks found no room: each chunk's weights
// (from its room, or from `spill` where it had none) at the start of a new room of an eighth
// more than it needs (and 64), in chunk order. pair_w does not shrink (the search borrows it).
void SphSolver::Impl::place_weights() {
  std::size_t total = 0;
  for (const std::size_t w : chunk_w_count) total += w + w / 8 + 64;
  std::vector<double> placed(std::max(total, pair_w.size()));
  std::size_t at = 0;
  for (std::size_t c = 0; c < chunk_w.size(); ++c) {
    const double* from = spill[c].empty() ? pair_w.data() + chunk_w[c] : spill[c].data();
    std::copy(from, from + chunk_w_count[c], placed.data() + at);
    chunk_w[c] = at;
    chunk_room[c] = chunk_w_count[c] + chunk_w_count[c] / 8 + 64;
    at += chunk_room[c];
    std::vector<double>().swap(spill[c]);
  }
  pair_w.swap(placed);
}

// The forces pass over chunk c's particles, their weights written straight into the chunk's room
// in pair_w; a particle that might not fit (it writes at most its pair count) moves them to the
// thread's buffer, and they end in spill[c]. Returns whether they did.
bool SphSolver::Impl::forces_chunk(std::size_t c, const ks::PairInputs& in,
                                   const ks::ForceInputs& f) {
  const std::size_t n = s.particles_.size();
  const std::size_t begin = c * kPairGrain;
  const std::size_t end = std::min(n, begin + kPairGrain);
  ks::ForceOutputs out{ax.data(),       ay.data(),    az.data(),
                       heat.data(),     h_mid.data(), pair_w.data() + chunk_w[c],
                       pair_mask.data()};
  std::size_t w = 0, g = chunk_mask[c];
  bool spilt = false;
  for (std::size_t i = begin; i < end; ++i) {
    const std::size_t half = active_count[i] - upper_at[i];
    if (!spilt && w + half > chunk_room[c]) {
      std::vector<double>& packed = packing.local();
      std::size_t pairs = w;
      for (std::size_t k = i; k < end; ++k) pairs += active_count[k] - upper_at[k];
      if (packed.size() < pairs) packed.resize(pairs);
      std::copy(out.pair_w, out.pair_w + w, packed.data());
      out.pair_w = packed.data();
      spilt = true;
    }
    w += ks::forces_upper<simd::Batch>(in, f, search.begin_of(i) + upper_at[i], half, i, n,
                                       rows8.data(), out, w, g);
    g += groups(half);
  }
  chunk_w_count[c] = w;
  if (spilt) {
    // One past the weights, so that a spilt chunk is never empty (place_weights).
    spill[c].reserve(w + 1);
    spill[c].assign(out.pair_w, out.pair_w + w);
    spill[c].push_back(0.0);
  }
  return spilt;
}

void SphSolver::Impl::forces() {
  ParticleStore& P = s.particles_;
  const std::size_t n = P.size();
  const double* rho = P.col(Field::rho).data();
  const double* sig[6];
  for (int c = 0; c < 6; ++c) sig[c] = P.col(kStressOrder[c]).data();
  const bool normalized = s.sph_.continuity == Continuity::normalized;
  rows8.resize(8 * n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (int c = 0; c < 6; ++c) {
                        for (std::size_t p = r.begin(); p < r.end(); ++p) {
                          a_stress[c][p] = normalized ? sig[c][p] : sig[c][p] / (rho[p] * rho[p]);
                        }
                      }
                      // The sums start at zero (the passes add the pairs' shares).
                      std::fill(rows8.data() + 8 * r.begin(), rows8.data() + 8 * r.end(), 0.0);
                      std::fill(h_mid.data() + r.begin(), h_mid.data() + r.end(), 0.0);
                    });
  if (mirrors) {
    mirror_stress(n);
    refresh_ghost_state();
  }
  const ks::PairInputs in = inputs();
  ks::ForceInputs f;
  for (int c = 0; c < 6; ++c) f.a_stress[c] = a_stress[c].data();
  f.soundspeed = mirrors ? ec.data() : P.col(Field::soundspeed).data();
  f.normalized = normalized;
  f.viscosity.alpha = s.sph_.alpha;
  f.viscosity.beta = s.sph_.beta;
  if (switch_on) {
    if (mirrors) mirror_scalar(alpha.data(), n);
    f.alpha = alpha.data();
  }
  compact_lists(in);
  const std::size_t chunks = chunk_mask.size() - 1;
  // Chunks new since the last layout have no room: they spill, and the pass lays pair_w out anew.
  chunk_w.resize(chunks, 0);
  chunk_room.resize(chunks, 0);
  chunk_w_count.resize(chunks);
  spill.resize(chunks);
  if (pair_w.empty()) pair_w.assign(1, 0.0);  // a valid pointer for the rates pass
  std::atomic<bool> spilled{false};
  over_tiles([&](std::size_t c) {
    if (forces_chunk(c, in, f)) spilled.store(true, std::memory_order_relaxed);
  });
  if (spilled.load()) place_weights();
  const auto& g = s.config_.gravity;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t p = r.begin(); p < r.end(); ++p) {
                        const double* row = rows8.data() + 8 * p;
                        ax[p] = row[0] + g[0];
                        ay[p] = row[1] + g[1];
                        az[p] = row[2] + g[2];
                        heat[p] = row[3];
                      }
                    });
  if (s.config_.self_gravity.self) add_self_gravity();
  // The images' a^n, for the next kick's viscous heat (rates pass).
  if (mirrors) mirror_vector(ax.data(), ay.data(), az.data(), n);
}

}  // namespace shatter::sph
