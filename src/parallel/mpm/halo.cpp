// The halo exchange of node sums (docs/mpi.md): partial sums of halo blocks go to the block's
// owner, which forms each node's sum from the partials of every colour in colour order,
// starting from zero, as the single process does (SparseGrid: every node gets at most one
// partial per colour), mirrors the symmetry and fixed planes, and sends the sums back to the
// ranks that sent partials. Messages are aggregated per neighbour rank: one each way per pair
// and call.

#include <cstring>
#include <stdexcept>
#include <unordered_map>

#include "mpm/loops.hpp"
#include "mpm/state.hpp"
#include "parallel/mpm/exchanges.hpp"

namespace shatter::parallel {
namespace {

constexpr int BN = SparseGrid::kBlockNodes;
constexpr int kColours = SparseGrid::kColours;

// A block whose sums this rank forms.
struct Target {
  std::int64_t block = -1;  // local block, or -1: a block only other ranks' particles reach
  std::size_t temp = 0;     // then its sums live in Reduction::temp from here
  std::array<const double*, kColours> src{};  // partial of each colour, or null
};

struct Reduction {
  mpm::State& s;
  NodeFields fields;
  std::size_t width;  // doubles per block: fields x nodes
  std::vector<Target> targets;
  std::unordered_map<std::uint64_t, std::size_t> index;  // block key -> target
  std::vector<double> temp;
  std::vector<std::vector<std::size_t>> reply;  // per rank: targets it sent, in its order
  std::vector<std::vector<double>> received;    // per rank: its message, copied as doubles

  // Field f (an index of NodeFields) of target t's nodes.
  double* field(const Target& t, int f) {
    if (t.block >= 0) {
      return mpm::node_fields(s.grid.nodes())[static_cast<std::size_t>(f)]->data() +
             static_cast<std::size_t>(t.block) * BN;
    }
    return temp.data() + t.temp + static_cast<std::size_t>(f - fields.first) * BN;
  }
};

std::uint64_t key_of(const mpm::State& s, std::uint32_t b) {
  const SparseGrid::Coord c = s.grid.coord(b);
  return SparseGrid::key(c.x, c.y, c.z);
}

// 1. partials of ghost blocks, by owner rank: key, colour mask, one block of values per colour
std::vector<Bytes> pack_partials(Reduction& red) {
  Ranks& R = red.s.ranks;
  HaloPlan& halo = R.halo;
  std::vector<Bytes> send(static_cast<std::size_t>(R.comm.size()));
  for (std::size_t h = 0; h < halo.blocks.size(); ++h) {
    if (halo.owner[h] == R.comm.rank()) continue;
    auto& out = send[static_cast<std::size_t>(halo.owner[h])];
    put(out, key_of(red.s, halo.blocks[h]));
    std::uint64_t mask = 0;
    for (int col = 0; col < kColours; ++col) {
      if (halo.slot_of(h, col) >= 0) mask |= 1u << col;
    }
    put(out, mask);
    for (int col = 0; col < kColours; ++col) {
      const std::int32_t sl = halo.slot_of(h, col);
      if (sl >= 0) put(out, halo.partial(sl, red.fields), red.width);
    }
  }
  return send;
}

// 2. the owner's targets: its own halo blocks with their local partials
void own_targets(Reduction& red) {
  HaloPlan& halo = red.s.ranks.halo;
  for (std::size_t h = 0; h < halo.blocks.size(); ++h) {
    if (halo.owner[h] != red.s.ranks.comm.rank()) continue;
    Target t;
    t.block = halo.blocks[h];
    for (int col = 0; col < kColours; ++col) {
      const std::int32_t sl = halo.slot_of(h, col);
      if (sl >= 0) t.src[static_cast<std::size_t>(col)] = halo.partial(sl, red.fields);
    }
    red.index.emplace(key_of(red.s, halo.blocks[h]), red.targets.size());
    red.targets.push_back(t);
  }
}

// ... and every partial rank q sent (its message copied into doubles first: the reads below
// are plain double reads, never a cast of the byte buffer).
void received_targets(Reduction& red, std::size_t q, const Bytes& b) {
  constexpr std::size_t kWord = sizeof(double);
  std::vector<double>& words = red.received[q];
  words.resize(b.size() / kWord);
  // An empty message leaves words.data() null, which memcpy may not be given even for 0 bytes.
  if (!words.empty()) std::memcpy(words.data(), b.data(), words.size() * kWord);
  std::size_t at = 0;  // in words
  while (at * kWord < b.size()) {
    std::uint64_t k = 0, mask = 0;
    std::memcpy(&k, b.data() + at * kWord, kWord);
    std::memcpy(&mask, b.data() + (at + 1) * kWord, kWord);
    at += 2;
    auto [it, fresh] = red.index.emplace(k, red.targets.size());
    if (fresh) {
      if (red.s.grid.find(k) >= 0) {
        throw std::logic_error("halo: partials for an owned block outside the halo plan");
      }
      Target t;
      t.temp = red.temp.size();
      red.temp.resize(red.temp.size() + red.width);
      red.targets.push_back(t);
    }
    Target& t = red.targets[it->second];
    for (int col = 0; col < kColours; ++col) {
      if (!(mask >> col & 1)) continue;
      if (t.src[static_cast<std::size_t>(col)] != nullptr) {
        throw std::logic_error("halo: two partials of one colour for one block");
      }
      t.src[static_cast<std::size_t>(col)] = words.data() + at;
      at += red.width;
    }
    red.reply[q].push_back(it->second);
  }
}

// Each target's node sums: the partials added in colour order, from zero.
void sum_targets(Reduction& red) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, red.targets.size(), 16),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t t = r.begin(); t < r.end(); ++t) {
                        const Target& tg = red.targets[t];
                        for (int f = red.fields.first; f < red.fields.end; ++f) {
                          double* out = red.field(tg, f);
                          const auto off = static_cast<std::size_t>(f - red.fields.first) * BN;
                          for (int l = 0; l < BN; ++l) {
                            double v = 0.0;
                            for (int col = 0; col < kColours; ++col) {
                              const double* src = tg.src[static_cast<std::size_t>(col)];
                              if (src != nullptr) v += src[off + static_cast<std::size_t>(l)];
                            }
                            out[l] = v;
                          }
                        }
                      }
                    });
}

// The unresolved kinetic energy's node sum (stages/grid_update.cpp) on several ranks: every node
// by its owner, from the complete sums before they are mirrored, as one process sums its nodes
// before its mirror. Owned blocks outside the halo are complete after the scatter (no other rank
// reaches them, none is near a plane); owned halo blocks are the targets, local or not.
void unresolved_on_owners(Reduction& red) {
  mpm::State& s = red.s;
  const auto F = mpm::node_fields(s.grid.nodes());
  std::vector<std::uint8_t> target(s.grid.blocks(), 0);
  for (const Target& tg : red.targets) {
    if (tg.block >= 0) target[static_cast<std::size_t>(tg.block)] = 1;
  }
  const auto& owned = s.ranks.halo.owned;
  ExactSum acc = mpm::node_unresolved(
      s.grid.blocks(), [&](std::uint32_t b) { return owned[b] != 0 && target[b] == 0; },
      [&](std::uint32_t b, int f) {
        return F[static_cast<std::size_t>(f)]->data() + std::size_t{b} * BN;
      });
  for (const Target& tg : red.targets) {
    const double* v[4];
    for (int f = 0; f < 4; ++f) v[f] = red.field(tg, f);
    mpm::add_node_unresolved(v, acc);
  }
  s.sums.unresolved = acc;
}

// 2b. symmetry and fixed planes, on the owner's complete sums (every block near a plane is a
// halo block, and a ghost and its partner have one owner: Decomposition::set_planes)
void mirror_targets(Reduction& red) {
  struct Blocks {
    Reduction& red;
    std::vector<SparseGrid::Coord> coords;
    std::size_t size() const { return red.targets.size(); }
    SparseGrid::Coord coord(std::size_t i) const { return coords[i]; }
    std::int64_t find(std::uint64_t k) const {
      const auto it = red.index.find(k);
      return it == red.index.end() ? -1 : static_cast<std::int64_t>(it->second);
    }
    double* field(std::size_t i, int f) { return red.field(red.targets[i], f); }
  } blocks{red, {}};
  blocks.coords.resize(red.targets.size());
  for (const auto& [k, i] : red.index) blocks.coords[i] = SparseGrid::decode(k);
  red.s.boundaries.mirror_blocks(blocks, red.fields.first == 0 ? mpm::Boundaries::kMassMomentumForce
                                                               : mpm::Boundaries::kMomentum);
}

// 3. the sums back to the ranks that sent partials, in the order they sent them
void return_sums(Reduction& red) {
  Ranks& R = red.s.ranks;
  HaloPlan& halo = R.halo;
  const auto ranks = static_cast<std::size_t>(R.comm.size());
  std::vector<Bytes> back(ranks), back_in(ranks);
  for (std::size_t q = 0; q < ranks; ++q) {
    for (const std::size_t t : red.reply[q]) {
      for (int f = red.fields.first; f < red.fields.end; ++f) {
        put(back[q], red.field(red.targets[t], f), BN);
      }
    }
    back_in[q].resize(halo.ghosts_to[q] * red.width * sizeof(double));
  }
  R.comm.exchange_known(back, back_in, &R.halo_traffic);
  const auto F = mpm::node_fields(red.s.grid.nodes());
  std::vector<std::size_t> read(ranks, 0);
  for (std::size_t h = 0; h < halo.blocks.size(); ++h) {
    if (halo.owner[h] == R.comm.rank()) continue;
    const auto q = static_cast<std::size_t>(halo.owner[h]);
    const std::byte* src = back_in[q].data() + read[q];
    read[q] += red.width * sizeof(double);
    const std::size_t at = std::size_t{halo.blocks[h]} * BN;
    for (int f = red.fields.first; f < red.fields.end; ++f) {
      std::memcpy(F[static_cast<std::size_t>(f)]->data() + at,
                  src + static_cast<std::size_t>(f - red.fields.first) * BN * sizeof(double),
                  BN * sizeof(double));
    }
  }
}

}  // namespace

void halo_reduce(mpm::State& s, NodeFields fields) {
  Ranks& R = s.ranks;
  const auto ranks = static_cast<std::size_t>(R.comm.size());
  Reduction red{s, fields, static_cast<std::size_t>(fields.count()) * BN, {}, {}, {}, {}, {}};
  red.reply.resize(ranks);
  red.received.resize(ranks);
  const std::vector<Bytes> recv = R.comm.exchange(pack_partials(red), &R.halo_traffic);
  own_targets(red);
  for (std::size_t q = 0; q < ranks; ++q) {
    if (static_cast<int>(q) != R.comm.rank()) received_targets(red, q, recv[q]);
  }
  sum_targets(red);
  if (fields.first == kForceExchange.first) unresolved_on_owners(red);
  bool planes = false;
  for (const auto& pl : s.boundaries.planes()) {
    planes = planes || pl.kind == BoundaryKind::symmetry || pl.kind == BoundaryKind::fixed;
  }
  if (planes) mirror_targets(red);
  return_sums(red);
}

mpm::Stage halo_stage(mpm::State& s) {
  return {"halo", {{}, mpm::kBlocks}, {{}, mpm::kGrid}, [&s] { halo_reduce(s, kForceExchange); }};
}

mpm::Stage momentum_halo_stage(mpm::State& s, const mpm::Stage& scatter, bool filter_pass) {
  return {"halo_" + scatter.name, scatter.reads, scatter.writes, [&s, filter_pass] {
            if (filter_pass && !s.filtering) return;  // no scatter ran, on every rank alike
            halo_reduce(s, kMomentumExchange);
          }};
}

}  // namespace shatter::parallel
