#pragma once
// Domain decomposition of the sparse grid's blocks over ranks (issue 15, docs/mpi.md): blocks
// are ordered along a Morton (Z-order) curve of their coordinates and the curve is cut into one
// contiguous piece per rank of about equal particle count. A particle belongs to the rank that
// owns its owner block; every block key, allocated or not, maps to exactly one rank, so any rank
// can tell where a particle or a node sum must go without asking.

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "shatter/core/particles.hpp"
#include "shatter/parallel/comm.hpp"

namespace shatter::parallel {

// Morton code of a SparseGrid block key (three 21-bit coordinates interleaved).
std::uint64_t morton(std::uint64_t block_key);

class Decomposition {
 public:
  // Cuts the curve from (block key, particle count) pairs; every rank must pass the same pairs
  // (in any order). Ranks past the particles get empty pieces.
  void build(std::vector<std::pair<std::uint64_t, std::int64_t>> weights, int ranks);
  int rank_of(std::uint64_t block_key) const;
  // Symmetry and fixed planes (axis, node index): the blocks within a stencil's reach of a
  // plane, on both sides, are placed as the block holding the plane, so a ghost node beyond it
  // and its partner always have one owner (who folds and mirrors them: docs/mpi.md).
  void set_planes(std::vector<std::pair<int, std::int64_t>> planes) { planes_ = std::move(planes); }
  // The block whose place on the curve block_key takes (itself away from planes).
  std::uint64_t placed(std::uint64_t block_key) const;
  // Within a stencil's reach (3 nodes) of a plane.
  bool near_plane(std::uint64_t block_key) const;
  bool built() const { return !cuts_.empty(); }
  // The first Morton code of each rank's piece.
  const std::vector<std::uint64_t>& cuts() const { return cuts_; }

 private:
  std::vector<std::uint64_t> cuts_;
  std::vector<std::pair<int, std::int64_t>> planes_;
};

// Particle rows for a transfer: the group index and every registered column of the listed
// particles. Stores on all ranks register the same columns and groups (they are built from
// one scene), which unpack() checks through the row width.
Bytes pack_particles(const ParticleStore& P, std::span<const std::uint32_t> which);
// A store with the same columns and groups as `like`: the particles of `like` whose keep flag
// is set (in their order), then the received rows, each appended to its group.
ParticleStore merge_particles(const ParticleStore& like, std::span<const std::uint8_t> keep,
                              const std::vector<Bytes>& received);
// Re-orders each group by particle id (the order of gathered output files).
void sort_by_id(ParticleStore& P);
// Every rank's particles in one store on rank 0, groups kept, each group sorted by id; other
// ranks get an empty store. With one rank: a copy sorted by id.
ParticleStore gather_particles(const ParticleStore& local, const Comm& comm);

}  // namespace shatter::parallel
