// The halo plan (docs/mpi.md): which blocks' node sums several ranks form, who owns them, and
// where each colour's local partial sums are kept; and the zeroing and capture of those
// partials inside a scatter's colour loop.

#include <algorithm>

#include "mpm/loops.hpp"
#include "mpm/state.hpp"
#include "parallel/mpm/exchanges.hpp"

namespace shatter::parallel {
namespace {

// Colour mask of the owner blocks b - s (s in {0,1}^3) of this rank that hold particles: the
// only blocks whose stencils reach b. remote: some of them belong to another rank.
std::uint32_t local_reach(const mpm::State& s, const SparseGrid::Coord& c, bool& remote) {
  const Ranks& R = s.ranks;
  std::uint32_t colours = 0;
  for (int sft = 0; sft < 8; ++sft) {
    const std::int64_t o[3] = {std::int64_t{c.x} - (sft & 1), std::int64_t{c.y} - ((sft >> 1) & 1),
                               std::int64_t{c.z} - ((sft >> 2) & 1)};
    const std::uint64_t ok = SparseGrid::key(o[0], o[1], o[2]);
    if (R.decomp.rank_of(ok) != R.comm.rank()) {
      remote = true;
      continue;
    }
    const std::int64_t ob = s.grid.find(ok);
    if (ob < 0 || s.grid.owned(static_cast<std::uint32_t>(ob)).empty()) continue;
    colours |= 1u << ((o[0] & 1) | ((o[1] & 1) << 1) | ((o[2] & 1) << 2));
  }
  return colours;
}

}  // namespace

void build_halo_plan(mpm::State& s) {
  Ranks& R = s.ranks;
  HaloPlan& halo = R.halo;
  R.plan_version = R.decomp_version;
  const int me = R.comm.rank();
  const std::size_t nb = s.grid.blocks();
  halo.blocks.clear();
  halo.owner.clear();
  halo.slot.clear();
  for (auto& c : halo.by_colour) c.clear();
  halo.owned.assign(nb, 0);
  halo.ghosts_to.assign(static_cast<std::size_t>(R.comm.size()), 0);
  std::int32_t slots = 0;
  for (std::uint32_t b = 0; b < nb; ++b) {
    const SparseGrid::Coord c = s.grid.coord(b);
    const std::uint64_t k = SparseGrid::key(c.x, c.y, c.z);
    const int owner = R.decomp.rank_of(k);
    halo.owned[b] = owner == me ? 1 : 0;
    // Blocks near a symmetry or fixed plane always go through their owner, who mirrors them.
    bool remote = owner != me || R.decomp.near_plane(k);
    const std::uint32_t colours = local_reach(s, c, remote);
    if (!remote) continue;
    const auto h = static_cast<std::uint32_t>(halo.blocks.size());
    halo.blocks.push_back(b);
    halo.owner.push_back(owner);
    if (owner != me) ++halo.ghosts_to[static_cast<std::size_t>(owner)];
    for (int col = 0; col < SparseGrid::kColours; ++col) {
      const bool reached = (colours >> col & 1u) != 0;
      halo.slot.push_back(reached ? slots++ : -1);
      if (reached) halo.by_colour[static_cast<std::size_t>(col)].push_back(h);
    }
  }
  halo.slots.resize(static_cast<std::size_t>(slots) * kNodeFields * SparseGrid::kBlockNodes);
}

void halo_zero(mpm::State& s, int colour, NodeFields fields) {
  const HaloPlan& halo = s.ranks.halo;
  const auto F = mpm::node_fields(s.grid.nodes());
  for (const std::uint32_t h : halo.by_colour[static_cast<std::size_t>(colour)]) {
    const std::size_t at = std::size_t{halo.blocks[h]} * SparseGrid::kBlockNodes;
    // the mass of a momentum-only scatter is step 1's and stays
    for (int f = fields.first; f < fields.end; ++f) {
      std::fill_n(F[static_cast<std::size_t>(f)]->begin() + static_cast<std::ptrdiff_t>(at),
                  SparseGrid::kBlockNodes, 0.0);
    }
  }
}

void halo_capture(mpm::State& s, int colour, NodeFields fields) {
  HaloPlan& halo = s.ranks.halo;
  const auto F = mpm::node_fields(s.grid.nodes());
  constexpr int BN = SparseGrid::kBlockNodes;
  for (const std::uint32_t h : halo.by_colour[static_cast<std::size_t>(colour)]) {
    const std::size_t at = std::size_t{halo.blocks[h]} * BN;
    double* out = halo.partial(halo.slot_of(h, colour), fields);
    for (int f = fields.first; f < fields.end; ++f) {
      std::copy_n(F[static_cast<std::size_t>(f)]->begin() + static_cast<std::ptrdiff_t>(at), BN,
                  out + (f - fields.first) * BN);
    }
  }
}

}  // namespace shatter::parallel
