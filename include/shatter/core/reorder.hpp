#pragma once
// The re-order of the particle store by a key within each material group.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <numeric>
#include <vector>

#include "shatter/core/particles.hpp"

namespace shatter {

// Re-orders each material group by key(p) (stable: equal keys keep their order, so the result
// is deterministic), the re-order both methods share (SPH by cell, the gathered output by id).
// `order` is left holding the permutation applied: new particle k is old particle order[k].
template <class Key>
void reorder_groups_by(ParticleStore& P, std::vector<std::uint32_t>& order, const Key& key) {
  order.resize(P.size());
  std::iota(order.begin(), order.end(), 0U);
  for (const Group& g : P.groups()) {
    std::stable_sort(order.begin() + static_cast<std::ptrdiff_t>(g.range.begin),
                     order.begin() + static_cast<std::ptrdiff_t>(g.range.end),
                     [&](std::uint32_t a, std::uint32_t b) { return key(a) < key(b); });
  }
  P.permute(order);
}

}  // namespace shatter
