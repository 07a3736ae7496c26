// Particle migration and load balance (docs/mpi.md): particles live on the rank that owns
// their owner block; the space-filling curve is recut from every rank's (block, particles)
// pairs when the load is uneven. Ownership moves, values do not.

#include <algorithm>
#include <bit>
#include <utility>

#include "mpm/loops.hpp"
#include "mpm/stages/stages.hpp"
#include "mpm/state.hpp"
#include "parallel/mpm/exchanges.hpp"

namespace shatter::parallel {
namespace {

// (owner block key, particles) pairs of sorted keys, flattened: key bits, count, key bits, ...
std::vector<std::int64_t> block_weights(const std::vector<std::uint64_t>& owner_keys) {
  std::vector<std::uint64_t> keys(owner_keys);
  std::sort(keys.begin(), keys.end());
  std::vector<std::int64_t> flat;
  for (std::size_t k = 0; k < keys.size(); ++k) {
    if (k == 0 || keys[k] != keys[k - 1]) {
      flat.push_back(std::bit_cast<std::int64_t>(keys[k]));
      flat.push_back(0);
    }
    ++flat.back();
  }
  return flat;
}

std::vector<std::pair<std::uint64_t, std::int64_t>> unflatten(std::span<const std::int64_t> all) {
  std::vector<std::pair<std::uint64_t, std::int64_t>> weights;
  weights.reserve(all.size() / 2);
  for (std::size_t k = 0; k + 1 < all.size(); k += 2) {
    weights.emplace_back(std::bit_cast<std::uint64_t>(all[k]), all[k + 1]);
  }
  return weights;
}

void rebalance_if_needed(mpm::State& s) {
  Ranks& R = s.ranks;
  if (s.clock.step % R.rebalance_every != 0) return;
  const std::int64_t mine[1] = {static_cast<std::int64_t>(s.owner_keys.size())};
  const auto counts = R.comm.allgather(mine);
  std::int64_t total = 0, most = 0;
  for (const std::int64_t c : counts) {
    total += c;
    most = std::max(most, c);
  }
  const double mean = static_cast<double>(total) / static_cast<double>(counts.size());
  if (!(static_cast<double>(most) > R.imbalance * mean)) return;
  // Recut from every rank's (owner block, particles) pairs.
  const auto all = R.comm.allgather(block_weights(s.owner_keys));
  R.decomp.build(unflatten(all), R.comm.size());
  ++R.decomp_version;
  ++R.rebalances;
}

template <class Shape>
void migrate(mpm::State& s) {
  ParticleStore& P = s.particles;
  Ranks& R = s.ranks;
  mpm::compute_keys<Shape>(s);
  rebalance_if_needed(s);
  const auto ranks = static_cast<std::size_t>(R.comm.size());
  const auto me = static_cast<std::size_t>(R.comm.rank());
  std::vector<std::vector<std::uint32_t>> leaving(ranks);
  std::vector<std::uint8_t> keep(P.size(), 1);
  for (std::size_t p = 0; p < P.size(); ++p) {
    const auto r = static_cast<std::size_t>(R.decomp.rank_of(s.owner_keys[p]));
    if (r == me) continue;
    keep[p] = 0;
    leaving[r].push_back(static_cast<std::uint32_t>(p));
  }
  std::vector<Bytes> send(ranks);
  bool moved = false;
  for (std::size_t r = 0; r < ranks; ++r) {
    if (leaving[r].empty()) continue;
    send[r] = pack_particles(P, leaving[r]);
    moved = true;
  }
  std::vector<Bytes> received = R.comm.exchange(send, &R.migrate_traffic);
  received[me].clear();
  for (const auto& b : received) moved = moved || !b.empty();
  // Arrivals go to the end of their group; their place in the store changes no sum (the order
  // inside a block is by id, the energy sums are exact).
  if (!moved) return;
  // (the step retake's journal, attached to the store, keeps the store at t^n)
  P.replace(merge_particles(P, keep, received));
}

}  // namespace

template <class Shape>
void distribute(mpm::State& s) {
  // Every rank holds every particle here: the first cut needs no communication.
  Ranks& R = s.ranks;
  mpm::compute_keys<Shape>(s);
  R.decomp.build(unflatten(block_weights(s.owner_keys)), R.comm.size());
  ++R.decomp_version;
  ParticleStore& P = s.particles;
  std::vector<std::uint8_t> keep(P.size());
  for (std::size_t p = 0; p < P.size(); ++p) {
    keep[p] = R.decomp.rank_of(s.owner_keys[p]) == R.comm.rank() ? 1 : 0;
  }
  P = merge_particles(P, keep, {});
}

template <class Shape>
mpm::Stage migrate_stage(mpm::State& s) {
  return {"migrate", {mpm::kGeometry, mpm::kClock}, {mpm::all_fields(), mpm::kBlocks}, [&s] {
            migrate<Shape>(s);
          }};
}

#define SHATTER_INSTANTIATE(S)              \
  template void distribute<S>(mpm::State&); \
  template mpm::Stage migrate_stage<S>(mpm::State&);
SHATTER_FOR_EACH_SHAPE(SHATTER_INSTANTIATE)

}  // namespace shatter::parallel
