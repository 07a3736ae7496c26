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
  // gx, gy, gz: mass gradient sum_p m_p grad N_I(x_p) of each body field (contact normals),
  // held for body copies only: index (node - shared_blocks() * kBlockNodes); empty without them.
  struct Nodes {
    std::vector<double> mass, px, py, pz, fx, fy, fz;
    std::vector<double> gx, gy, gz;
  };

  // A shared block reached by the stencils of several bodies (multi-velocity-field contact):
  // its field lives in `count` body copies, blocks first_copy .. first_copy + count - 1, with
  // bodies in increasing order; the shared block itself then stays empty.
  struct Meeting {
    std::uint32_t block, first_copy, count;
  };

  static std::uint64_t key(std::int64_t bx, std::int64_t by, std::int64_t bz) {
    constexpr std::int64_t off = std::int64_t{1} << 20;
    return (static_cast<std::uint64_t>(bx + off) << 42) |
           (static_cast<std::uint64_t>(by + off) << 21) | static_cast<std::uint64_t>(bz + off);
  }
  // The inverse of key.
  static Coord decode(std::uint64_t k) {
    constexpr std::int64_t off = std::int64_t{1} << 20;
    constexpr std::uint64_t mask = (std::uint64_t{1} << 21) - 1;
    return {static_cast<std::int32_t>(static_cast<std::int64_t>((k >> 42) & mask) - off),
            static_cast<std::int32_t>(static_cast<std::int64_t>((k >> 21) & mask) - off),
            static_cast<std::int32_t>(static_cast<std::int64_t>(k & mask) - off)};
  }
  static int local(int lx, int ly, int lz) { return (lx * kBlock + ly) * kBlock + lz; }

  // Rebuilds blocks, particle lists and colours from the owner-block keys of all particles
  // (particle order is kept inside each block's list). Returns false when nothing changed since
  // the last call (same keys in the same order), in which case nothing is rebuilt.
  //
  // `bodies` (optional, one body id per particle) switches on one velocity field per body where
  // several bodies meet: every block reached by the stencils of two or more bodies gets a copy
  // per body, appended after the shared blocks, and each particle scatters to and gathers from
  // its own body's copies (particle_neighbours). Blocks reached by one body are shared as
  // before, so memory grows only where bodies meet, and with one body nothing changes.
  //
  // `ids` (optional, one particle id per particle) makes the order inside each block's list
  // canonical: by (body, id) instead of by store index. The node sums then depend only on which
  // particles a block owns, not on where they sit in the store, so a run gives the same bits
  // on any number of ranks, whatever order migrants arrive in (docs/mpi.md).
  bool assign(std::span<const std::uint64_t> owner_keys, std::span<const std::int64_t> bodies = {},
              std::span<const std::int64_t> ids = {});

  // All blocks, body copies included (node arrays span them all).
  std::size_t blocks() const { return coords_.size(); }
  // Blocks of the shared grid; body copies have indices shared_blocks() .. blocks() - 1.
  std::size_t shared_blocks() const { return shared_; }
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
  // The 8 blocks particle p's stencil reaches, body copies where its body meets another.
  const std::uint32_t* particle_neighbours(std::size_t p) const {
    return list_of_.empty() ? neighbours(owner_[p]) : &neighbours_[list_of_[p]];
  }
  // Offset of particle p's neighbour list (equal offsets: same list); owner * 8 without bodies.
  std::uint32_t list_of(std::size_t p) const {
    return list_of_.empty() ? owner_[p] * 8 : list_of_[p];
  }
  const std::uint32_t* list(std::uint32_t offset) const { return &neighbours_[offset]; }
  bool has_copies() const { return blocks() > shared_; }

  std::span<const Meeting> meetings() const { return meetings_; }
  // A shared block whose field lives in body copies (it stays empty).
  bool meets(std::uint32_t b) const {
    return !meetings_.empty() && b < shared_ && meeting_of_[b] >= 0;
  }
  // Body of a copy block (b >= shared_blocks()).
  std::int64_t copy_body(std::uint32_t b) const { return copy_body_[b - shared_]; }
  // The block at key `k` that holds the same velocity field as block b: the shared block, or,
  // where bodies meet, the copy of b's body (-1 when that body does not reach it).
  std::int64_t find_like(std::uint32_t b, std::uint64_t k) const;

  Nodes& nodes() { return nodes_; }
  const Nodes& nodes() const { return nodes_; }
  void clear_nodes();

 private:
  // The pieces of assign(), in order.
  bool same_input(std::span<const std::uint64_t> owner_keys, std::span<const std::int64_t> bodies,
                  std::span<const std::int64_t> ids) const;
  void allocate_blocks(const std::vector<std::uint64_t>& owners);
  void link_neighbours(const std::vector<std::uint64_t>& owners);
  void sort_particles(std::span<const std::uint64_t> owner_keys,
                      std::span<const std::int64_t> bodies, std::span<const std::int64_t> ids);
  void size_nodes();
  // The body fields (see assign), and its pieces.
  void assign_bodies(std::span<const std::int64_t> bodies);
  std::vector<std::vector<std::int64_t>> find_meetings(const std::vector<std::uint32_t>& bstart,
                                                       const std::vector<std::int64_t>& blist);
  void add_copies(std::vector<std::vector<std::int64_t>>& sets);
  void link_copies(std::span<const std::int64_t> bodies, const std::vector<std::uint32_t>& bstart,
                   const std::vector<std::int64_t>& blist);

  std::vector<std::uint64_t> block_keys_;  // sorted

 public:
  // Keys of all blocks, sorted (the block index order).
  std::span<const std::uint64_t> block_keys() const { return block_keys_; }

 private:
  std::vector<Coord> coords_;
  std::unordered_map<std::uint64_t, std::uint32_t> index_;
  // 8 per shared block (valid for owner blocks), then 8 per (owner, body) of owners whose
  // stencils reach a block where bodies meet
  std::vector<std::uint32_t> neighbours_;
  // What same_input cannot read back from the lists: the bodies (contact runs only) and
  // whether ids were given; the keys and ids of the last assign are not kept (same_input).
  std::vector<std::int64_t> last_bodies_;
  bool last_ids_empty_ = true;
  std::array<std::vector<std::uint32_t>, kColours> colours_;
  std::vector<std::uint32_t> start_;      // CSR offsets per block
  std::vector<std::uint32_t> particles_;  // particle indices grouped by owner block
  std::vector<std::uint32_t> owner_;      // owner block per particle
  // Body fields (empty unless assign() got bodies and two of them meet)
  std::size_t shared_ = 0;                // shared blocks; copies follow
  std::vector<std::int64_t> block_body_;  // per shared block: its one body, -1 where bodies meet
  std::vector<std::int32_t> meeting_of_;  // per shared block: index into meetings_, or -1
  std::vector<Meeting> meetings_;
  std::vector<std::int64_t> copy_body_;  // per copy block
  std::vector<std::uint32_t> list_of_;   // per particle: offset of its neighbour list
  Nodes nodes_;
};

}  // namespace shatter
