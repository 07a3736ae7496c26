#include "shatter/grid/sparse_grid.hpp"

#include <algorithm>

#include <tbb/parallel_for.h>

namespace shatter {
namespace {

SparseGrid::Coord decode(std::uint64_t k) {
  constexpr std::int64_t off = std::int64_t{1} << 20;
  constexpr std::uint64_t mask = (std::uint64_t{1} << 21) - 1;
  return {static_cast<std::int32_t>(static_cast<std::int64_t>((k >> 42) & mask) - off),
          static_cast<std::int32_t>(static_cast<std::int64_t>((k >> 21) & mask) - off),
          static_cast<std::int32_t>(static_cast<std::int64_t>(k & mask) - off)};
}

}  // namespace

std::int64_t SparseGrid::find(std::uint64_t k) const {
  const auto it = index_.find(k);
  return it == index_.end() ? -1 : static_cast<std::int64_t>(it->second);
}

std::size_t SparseGrid::bytes() const {
  const std::size_t node_bytes = 7 * sizeof(double) * nodes_.mass.size();
  const std::size_t block_bytes =
      blocks() * (sizeof(std::uint64_t) + sizeof(Coord) + 8 * sizeof(std::uint32_t) +
                  sizeof(std::uint32_t) + 2 * sizeof(std::uint64_t) /* hash entry, approx */);
  const std::size_t particle_bytes = (particles_.size() + owner_.size()) * sizeof(std::uint32_t) +
                                     last_keys_.size() * sizeof(std::uint64_t);
  return node_bytes + block_bytes + particle_bytes;
}

bool SparseGrid::assign(std::span<const std::uint64_t> owner_keys) {
  const std::size_t n = owner_keys.size();
  if (n == last_keys_.size() &&
      std::equal(owner_keys.begin(), owner_keys.end(), last_keys_.begin())) {
    return false;
  }
  last_keys_.assign(owner_keys.begin(), owner_keys.end());

  // Owner blocks: particles are mostly block-sorted, so collecting the keys where the key changes
  // along the particle order gives a short list to sort.
  std::vector<std::uint64_t> owners;
  for (std::size_t p = 0; p < n; ++p) {
    if (p == 0 || owner_keys[p] != owner_keys[p - 1]) owners.push_back(owner_keys[p]);
  }
  std::sort(owners.begin(), owners.end());
  owners.erase(std::unique(owners.begin(), owners.end()), owners.end());

  // Allocated blocks: owners and the blocks their stencils spill into (+{0,1}^3).
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

  neighbours_.assign(nb * 8, 0);
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

  // Particle lists per owner block: a stable counting sort keeps the particle order inside each
  // block, which fixes the summation order at every node.
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

  const std::size_t nn = nb * kBlockNodes;
  for (auto* v :
       {&nodes_.mass, &nodes_.px, &nodes_.py, &nodes_.pz, &nodes_.fx, &nodes_.fy, &nodes_.fz}) {
    v->resize(nn);
  }
  return true;
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
}

}  // namespace shatter
