#pragma once
// What an MPM run over several ranks keeps between steps (docs/mpi.md): the decomposition of
// the grid blocks, when it was last recut, the halo plan built from it, and the traffic.
// With one rank nothing here is used: every exchange stage is left out of the step.

#include <array>
#include <cstdint>
#include <vector>

#include "shatter/grid/sparse_grid.hpp"
#include "shatter/parallel/comm.hpp"
#include "shatter/parallel/decomposition.hpp"

namespace shatter::parallel {

// The node arrays of SparseGrid::Nodes a halo exchange carries, as a range [first, end) of
// (mass, px, py, pz, fx, fy, fz).
struct NodeFields {
  int first;
  int end;
  constexpr int count() const { return end - first; }
};
constexpr int kNodeFields = 7;  // mass, momentum (3), force (3)
// The force-carrying P2G (App. A.2 step 1) exchanges every array.
constexpr NodeFields kForceExchange{0, kNodeFields};
// The MUSL remap and the XPIC/FMPM passes exchange momentum only: the mass is step 1's.
constexpr NodeFields kMomentumExchange{1, 4};

// Halo blocks: blocks another rank owns (ghosts: their partial sums go to the owner, the final
// sums come back) and owned blocks that owner blocks of other ranks may reach (their sums are
// formed from the partials of every rank, colour by colour, as in one process). Rebuilt when
// the grid or the decomposition changes.
struct HaloPlan {
  std::vector<std::uint32_t> blocks;  // local block index per halo block
  std::vector<int> owner;             // owner rank per halo block
  std::vector<std::int32_t> slot;     // per halo block x colour: slot of the local partial, or -1
  std::array<std::vector<std::uint32_t>, SparseGrid::kColours> by_colour;  // halo blocks
  std::vector<double> slots;           // slot x field x node (kNodeFields fields per slot)
  std::vector<std::uint8_t> owned;     // per local block: this rank owns it (energy sums)
  std::vector<std::size_t> ghosts_to;  // per rank: ghost blocks sent there

  std::int32_t slot_of(std::size_t h, int colour) const {
    return slot[h * SparseGrid::kColours + static_cast<std::size_t>(colour)];
  }
  // The partial of slot sl, field range f (kNodeFields x kBlockNodes doubles per slot).
  double* partial(std::int32_t sl, NodeFields f) {
    return slots.data() +
           (static_cast<std::size_t>(sl) * kNodeFields + static_cast<std::size_t>(f.first)) *
               SparseGrid::kBlockNodes;
  }
};

struct Ranks {
  const Comm& comm = world();
  bool dist = world().distributed();
  Decomposition decomp;
  std::uint64_t decomp_version = 0, plan_version = ~std::uint64_t{0};
  std::uint64_t rebalances = 0;
  // Load balance (docs/mpi.md): steps between load checks, and the max/mean particle count
  // that triggers a recut (SolverConfig, or the environment: see Simulation's constructor).
  unsigned rebalance_every = 10;
  double imbalance = 1.2;
  Traffic halo_traffic, migrate_traffic;
  HaloPlan halo;
};

}  // namespace shatter::parallel
