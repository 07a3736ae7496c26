#include "shatter/grid/sparse_grid.hpp"

#include <algorithm>

#include <tbb/parallel_for.h>

namespace shatter {
std::int64_t SparseGrid::find(std::uint64_t k) const {
  const auto it = index_.find(k);
  return it == index_.end() ? -1 : static_cast<std::int64_t>(it->second);
}

std::int64_t SparseGrid::find_like(std::uint32_t b, std::uint64_t k) const {
  const std::int64_t s = find(k);
  if (s < 0 || meetings_.empty()) return s;
  // The field of b's body: b is a copy, or a shared block of one body.
  const std::int64_t body = b >= shared_ ? copy_body_[b - shared_] : block_body_[b];
  const std::int32_t m = meeting_of_[static_cast<std::size_t>(s)];
  // A block of one body holds that body's field only.
  if (m < 0) return block_body_[static_cast<std::size_t>(s)] == body ? s : -1;
  const Meeting& mt = meetings_[static_cast<std::size_t>(m)];
  for (std::uint32_t c = mt.first_copy; c < mt.first_copy + mt.count; ++c) {
    if (copy_body_[c - shared_] == body) return c;
  }
  return -1;
}

std::size_t SparseGrid::bytes() const {
  const std::size_t node_bytes =
      7 * sizeof(double) * nodes_.mass.size() + 3 * sizeof(double) * nodes_.gx.size();
  const std::size_t block_bytes =
      blocks() * (sizeof(std::uint64_t) + sizeof(Coord) + 8 * sizeof(std::uint32_t) +
                  sizeof(std::uint32_t) + 2 * sizeof(std::uint64_t) /* hash entry, approx */);
  const std::size_t particle_bytes = (particles_.size() + owner_.size()) * sizeof(std::uint32_t) +
                                     last_bodies_.size() * sizeof(std::int64_t);
  return node_bytes + block_bytes + particle_bytes;
}

// The last assign's input, read back from what it built instead of kept as copies (16 B per
// particle): the owner key of particle p is block_keys_[owner_[p]] (owner_ indexes the shared
// blocks, which are block_keys_ in order), and the ids enter only through the order of each
// block's list, by (body, id). With the same keys and bodies, a rebuild gives the same lists
// exactly when every list is strictly ascending in (body, id) under the ids given now: a strict
// order has one sorted arrangement. (A list with equal (body, id) pairs is rebuilt.)
bool SparseGrid::same_input(std::span<const std::uint64_t> owner_keys,
                            std::span<const std::int64_t> bodies,
                            std::span<const std::int64_t> ids) const {
  const std::size_t n = owner_keys.size();
  if (n != owner_.size() || ids.empty() != last_ids_empty_ ||
      !std::ranges::equal(bodies, last_bodies_)) {
    return false;
  }
  for (std::size_t p = 0; p < n; ++p) {
    if (block_keys_[owner_[p]] != owner_keys[p]) return false;
  }
  if (ids.empty()) return true;
  const auto before = [&](std::uint32_t a, std::uint32_t c) {
    if (!bodies.empty() && bodies[a] != bodies[c]) return bodies[a] < bodies[c];
    return ids[a] < ids[c];
  };
  for (std::size_t b = 0; b + 1 < start_.size(); ++b) {
    for (std::uint32_t k = start_[b] + 1; k < start_[b + 1]; ++k) {
      if (!before(particles_[k - 1], particles_[k])) return false;
    }
  }
  return true;
}

// Allocated blocks: owners and the blocks their stencils spill into (+{0,1}^3), in key order.
void SparseGrid::allocate_blocks(const std::vector<std::uint64_t>& owners) {
  block_keys_.clear();
  block_keys_.reserve(owners.size() * 8);
  for (const std::uint64_t k : owners) {
    const Coord c = decode(k);
    for (int s = 0; s < 8; ++s) {
      block_keys_.push_back(key(c.x + (s & 1), c.y + ((s >> 1) & 1), c.z + ((s >> 2) & 1)));
    }
  }
  std::sort(block_keys_.begin(), block_keys_.end());
  block_keys_.erase(std::unique(block_keys_.begin(), block_keys_.end()), block_keys_.end());

  const std::size_t nb = block_keys_.size();
  coords_.resize(nb);
  index_.clear();
  index_.reserve(nb * 2);
  for (std::size_t b = 0; b < nb; ++b) {
    coords_[b] = decode(block_keys_[b]);
    index_.emplace(block_keys_[b], static_cast<std::uint32_t>(b));
  }
}

// The 8 blocks each owner's stencil reaches, and the owners by colour.
void SparseGrid::link_neighbours(const std::vector<std::uint64_t>& owners) {
  neighbours_.assign(block_keys_.size() * 8, 0);
  for (auto& c : colours_) c.clear();
  for (const std::uint64_t k : owners) {
    const std::uint32_t b = index_.at(k);
    const Coord c = coords_[b];
    for (int s = 0; s < 8; ++s) {
      neighbours_[b * 8 + s] =
          index_.at(key(c.x + (s & 1), c.y + ((s >> 1) & 1), c.z + ((s >> 2) & 1)));
    }
    colours_[(c.x & 1) | ((c.y & 1) << 1) | ((c.z & 1) << 2)].push_back(b);
  }
}

// Particle lists per owner block: a stable counting sort keeps the particle order inside each
// block, which fixes the summation order at every node.
void SparseGrid::sort_particles(std::span<const std::uint64_t> owner_keys,
                                std::span<const std::int64_t> bodies,
                                std::span<const std::int64_t> ids) {
  const std::size_t n = owner_keys.size();
  const std::size_t nb = block_keys_.size();
  owner_.resize(n);
  start_.assign(nb + 1, 0);
  std::uint64_t last_key = ~std::uint64_t{0};
  std::uint32_t last_block = 0;
  for (std::size_t p = 0; p < n; ++p) {
    if (owner_keys[p] != last_key) {
      last_key = owner_keys[p];
      last_block = index_.at(last_key);
    }
    owner_[p] = last_block;
    ++start_[last_block + 1];
  }
  for (std::size_t b = 0; b < nb; ++b) start_[b + 1] += start_[b];
  particles_.resize(n);
  std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
  for (std::size_t p = 0; p < n; ++p) particles_[fill[owner_[p]]++] = static_cast<std::uint32_t>(p);
  if (!ids.empty()) {
    // Canonical order inside each block: (body, id). Bodies stay contiguous, so the runs that
    // share a neighbour list (one per body where bodies meet) are the same as before.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nb, 64),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t b = r.begin(); b < r.end(); ++b) {
                          auto* first = particles_.data() + start_[b];
                          auto* last = particles_.data() + start_[b + 1];
                          std::sort(first, last, [&](std::uint32_t a, std::uint32_t c) {
                            if (!bodies.empty() && bodies[a] != bodies[c]) {
                              return bodies[a] < bodies[c];
                            }
                            return ids[a] < ids[c];
                          });
                        }
                      });
  }
}

void SparseGrid::size_nodes() {
  const std::size_t nn = blocks() * kBlockNodes;
  for (auto* v :
       {&nodes_.mass, &nodes_.px, &nodes_.py, &nodes_.pz, &nodes_.fx, &nodes_.fy, &nodes_.fz}) {
    v->resize(nn);
  }
  const std::size_t ng = (blocks() - shared_) * kBlockNodes;
  for (auto* v : {&nodes_.gx, &nodes_.gy, &nodes_.gz}) v->resize(ng);
}

bool SparseGrid::assign(std::span<const std::uint64_t> owner_keys,
                        std::span<const std::int64_t> bodies, std::span<const std::int64_t> ids) {
  if (same_input(owner_keys, bodies, ids)) return false;
  last_bodies_.assign(bodies.begin(), bodies.end());
  last_ids_empty_ = ids.empty();

  // Owner blocks: particles are mostly block-sorted, so collecting the keys where the key changes
  // along the particle order gives a short list to sort.
  std::vector<std::uint64_t> owners;
  for (std::size_t p = 0; p < owner_keys.size(); ++p) {
    if (p == 0 || owner_keys[p] != owner_keys[p - 1]) owners.push_back(owner_keys[p]);
  }
  std::sort(owners.begin(), owners.end());
  owners.erase(std::unique(owners.begin(), owners.end()), owners.end());

  allocate_blocks(owners);
  link_neighbours(owners);
  sort_particles(owner_keys, bodies, ids);
  shared_ = block_keys_.size();
  meetings_.clear();
  copy_body_.clear();
  list_of_.clear();
  if (!bodies.empty()) assign_bodies(bodies);
  size_nodes();
  return true;
}

// Blocks reached by several bodies (each owner's bodies reach its 8 neighbour blocks), each
// numbered as a meeting (meeting_of_), with the bodies that reach it (unsorted, repeated).
std::vector<std::vector<std::int64_t>> SparseGrid::find_meetings(
    const std::vector<std::uint32_t>& bstart, const std::vector<std::int64_t>& blist) {
  const std::size_t nb = shared_;
  constexpr std::int64_t kNone = -1, kSeveral = -2;
  block_body_.assign(nb, kNone);
  for (std::size_t o = 0; o < nb; ++o) {
    for (std::uint32_t k = bstart[o]; k < bstart[o + 1]; ++k) {
      for (int s = 0; s < 8; ++s) {
        std::int64_t& tag = block_body_[neighbours_[o * 8 + static_cast<std::size_t>(s)]];
        if (tag == kNone) {
          tag = blist[k];
        } else if (tag != blist[k]) {
          tag = kSeveral;
        }
      }
    }
  }
  // Their body sets.
  meeting_of_.assign(nb, -1);
  std::vector<std::vector<std::int64_t>> sets;
  for (std::size_t b = 0; b < nb; ++b) {
    if (block_body_[b] != kSeveral) continue;
    meeting_of_[b] = static_cast<std::int32_t>(sets.size());
    sets.emplace_back();
  }
  if (sets.empty()) return sets;
  for (std::size_t o = 0; o < nb; ++o) {
    for (int s = 0; s < 8; ++s) {
      const std::int32_t m = meeting_of_[neighbours_[o * 8 + static_cast<std::size_t>(s)]];
      if (m < 0) continue;
      auto& set = sets[static_cast<std::size_t>(m)];
      set.insert(set.end(), blist.begin() + bstart[o], blist.begin() + bstart[o + 1]);
    }
  }
  return sets;
}

// One copy per (meeting block, body), in block order, appended after the shared blocks.
void SparseGrid::add_copies(std::vector<std::vector<std::int64_t>>& sets) {
  const std::size_t nb = shared_;
  for (std::size_t b = 0; b < nb; ++b) {
    const std::int32_t m = meeting_of_[b];
    if (m < 0) continue;
    auto& set = sets[static_cast<std::size_t>(m)];
    std::sort(set.begin(), set.end());
    set.erase(std::unique(set.begin(), set.end()), set.end());
    meetings_.push_back({static_cast<std::uint32_t>(b), static_cast<std::uint32_t>(blocks()),
                         static_cast<std::uint32_t>(set.size())});
    const Coord c = coords_[b];
    for (const std::int64_t body : set) {
      coords_.push_back(c);
      copy_body_.push_back(body);
    }
  }
}

// Neighbour lists per (owner, body) for owners next to a meeting block; every other particle
// keeps its owner's list.
void SparseGrid::link_copies(std::span<const std::int64_t> bodies,
                             const std::vector<std::uint32_t>& bstart,
                             const std::vector<std::int64_t>& blist) {
  const std::size_t nb = shared_;
  list_of_.resize(owner_.size());
  for (std::size_t o = 0; o < nb; ++o) {
    bool near = false;
    for (int s = 0; s < 8; ++s)
      near |= meeting_of_[neighbours_[o * 8 + static_cast<std::size_t>(s)]] >= 0;
    const std::uint32_t first_list = static_cast<std::uint32_t>(neighbours_.size());
    if (near) {
      for (std::uint32_t k = bstart[o]; k < bstart[o + 1]; ++k) {
        for (int s = 0; s < 8; ++s) {
          const std::uint32_t nbr = neighbours_[o * 8 + static_cast<std::size_t>(s)];
          const std::int32_t m = meeting_of_[nbr];
          std::uint32_t target = nbr;
          if (m >= 0) {
            const Meeting& mt = meetings_[static_cast<std::size_t>(m)];
            for (std::uint32_t c = mt.first_copy; c < mt.first_copy + mt.count; ++c) {
              if (copy_body_[c - nb] == blist[k]) target = c;
            }
          }
          neighbours_.push_back(target);
        }
      }
    }
    for (std::uint32_t k = start_[o]; k < start_[o + 1]; ++k) {
      const std::uint32_t p = particles_[k];
      if (!near) {
        list_of_[p] = static_cast<std::uint32_t>(o * 8);
        continue;
      }
      const auto it =
          std::lower_bound(blist.begin() + bstart[o], blist.begin() + bstart[o + 1], bodies[p]);
      list_of_[p] = first_list + 8 * static_cast<std::uint32_t>(it - (blist.begin() + bstart[o]));
    }
  }
}

void SparseGrid::assign_bodies(std::span<const std::int64_t> bodies) {
  const std::size_t nb = shared_;
  // Bodies of each owner block's particles (sorted, distinct), CSR by owner block.
  std::vector<std::uint32_t> bstart(nb + 1, 0);
  std::vector<std::int64_t> blist;
  std::vector<std::int64_t> tmp;
  bool several = false;
  for (std::size_t b = 0; b < nb; ++b) {
    tmp.clear();
    for (std::uint32_t k = start_[b]; k < start_[b + 1]; ++k) {
      const std::int64_t body = bodies[particles_[k]];
      if (tmp.empty() || tmp.back() != body) tmp.push_back(body);
    }
    std::sort(tmp.begin(), tmp.end());
    tmp.erase(std::unique(tmp.begin(), tmp.end()), tmp.end());
    if (!blist.empty() && !tmp.empty() && tmp.front() != blist.front()) several = true;
    if (tmp.size() > 1) several = true;
    blist.insert(blist.end(), tmp.begin(), tmp.end());
    bstart[b + 1] = static_cast<std::uint32_t>(blist.size());
  }
  if (!several) return;  // one body: the shared grid is its field
  auto sets = find_meetings(bstart, blist);
  if (sets.empty()) return;
  add_copies(sets);
  link_copies(bodies, bstart, blist);
}

void SparseGrid::clear_nodes() {
  const std::size_t nn = nodes_.mass.size();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nn, 4096),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (auto* v : {&nodes_.mass, &nodes_.px, &nodes_.py, &nodes_.pz, &nodes_.fx,
                                      &nodes_.fy, &nodes_.fz}) {
                        std::fill(v->begin() + static_cast<std::ptrdiff_t>(r.begin()),
                                  v->begin() + static_cast<std::ptrdiff_t>(r.end()), 0.0);
                      }
                    });
  for (auto* v : {&nodes_.gx, &nodes_.gy, &nodes_.gz}) std::fill(v->begin(), v->end(), 0.0);
}

}  // namespace shatter
