#pragma once
// Sparse blocked background grid (ISSUE engine item 3; DESIGN.md "Grid"). Nodes live in blocks of
// 4x4x4 allocated only where particle stencils reach, so memory follows the number of active
// blocks, never the bounding box of the debris cloud.
//
// A particle belongs to the block of the first node of its stencil (its "owner" block). A 3-wide
// stencil starting anywhere in block b reaches at most blocks b + {0,1}^3, so owner blocks of one
// parity colour (bx&1, by&1, bz&1) never write the same node: P2G runs colour by colour with no
// atomics and no locks, and the sum at every node is formed in the same order whatever the thread
// count.

#include <array>
#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

namespace shatter {

class SparseGrid {
 public:
  static constexpr int kBlockBits = 2;
  static constexpr int kBlock = 1 << kBlockBits;  // nodes per block edge
  static constexpr int kBlockNodes = kBlock * kBlock * kBlock;
  static constexpr int kColours = 8;
  // Block coordinates are stored in 21 bits each (+-2^20 blocks): 4 million cells per axis.
  static constexpr std::int64_t kMaxBlockCoord = (std::int64_t{1} << 20) - 1;

  struct Coord {
    std::int32_t x, y, z;
  };

  // Node fields, one array each, indexed by block * kBlockNodes + local node.
  struct Nodes {
    std::vector<double> mass, px, py, pz, fx, fy, fz;
  };

  static std::uint64_t key(std::int64_t bx, std::int64_t by, std::int64_t bz) {
    constexpr std::int64_t off = std::int64_t{1} << 20;
    return (static_cast<std::uint64_t>(bx + off) << 42) |
           (static_cast<std::uint64_t>(by + off) << 21) | static_cast<std::uint64_t>(bz + off);
  }
  static int local(int lx, int ly, int lz) { return (lx * kBlock + ly) * kBlock + lz; }

  // Rebuilds blocks, particle lists and colours from the owner-block keys of all particles
  // (particle order is kept inside each block's list). Returns false when nothing changed since
  // the last call (same keys in the same order), in which case nothing is rebuilt.
  bool assign(std::span<const std::uint64_t> owner_keys);

  std::size_t blocks() const { return coords_.size(); }
  std::size_t bytes() const;
  const Coord& coord(std::uint32_t b) const { return coords_[b]; }
  // Index of the block with this key, or -1.
  std::int64_t find(std::uint64_t k) const;
  // Block index of b + (sx, sy, sz) with s in {0, 1}: always allocated for owner blocks.
  std::uint32_t neighbour(std::uint32_t owner, int s) const { return neighbours_[owner * 8 + s]; }
  const std::uint32_t* neighbours(std::uint32_t owner) const { return &neighbours_[owner * 8]; }

  // Owner blocks of one colour, and the particles each owns.
  std::span<const std::uint32_t> colour(int c) const { return colours_[c]; }
  std::span<const std::uint32_t> owned(std::uint32_t b) const {
    return {particles_.data() + start_[b], particles_.data() + start_[b + 1]};
  }
  std::span<const std::uint32_t> particle_order() const { return particles_; }
  std::uint32_t owner_of(std::size_t p) const { return owner_[p]; }

  Nodes& nodes() { return nodes_; }
  const Nodes& nodes() const { return nodes_; }
  void clear_nodes();

 private:
  std::vector<std::uint64_t> last_keys_;
  std::vector<std::uint64_t> block_keys_;  // sorted
  std::vector<Coord> coords_;
  std::unordered_map<std::uint64_t, std::uint32_t> index_;
  std::vector<std::uint32_t> neighbours_;  // 8 per block (valid for owner blocks)
  std::array<std::vector<std::uint32_t>, kColours> colours_;
  std::vector<std::uint32_t> start_;      // CSR offsets per block
  std::vector<std::uint32_t> particles_;  // particle indices grouped by owner block
  std::vector<std::uint32_t> owner_;      // owner block per particle
  Nodes nodes_;
};

}  // namespace shatter
