#include "fracture/cell_grid.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "shatter/fracture/counter_rng.hpp"

namespace shatter::fracture {

void radix_sort(std::vector<std::uint64_t>& keys, std::vector<std::uint32_t>& idx) {
  const std::size_t n = keys.size();
  std::vector<std::uint64_t> keys_tmp(n);
  std::vector<std::uint32_t> idx_tmp(n);
  std::vector<std::size_t> count(std::size_t{1} << 16);
  for (int shift = 0; shift < 64; shift += 16) {
    std::fill(count.begin(), count.end(), 0);
    for (std::uint64_t k : keys) ++count[(k >> shift) & 0xFFFFU];
    // A pass where every key has the same digit would only copy.
    if (n == 0 || count[(keys[0] >> shift) & 0xFFFFU] == n) continue;
    std::size_t sum = 0;
    for (auto& c : count) {
      const std::size_t here = c;
      c = sum;
      sum += here;
    }
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t dst = count[(keys[i] >> shift) & 0xFFFFU]++;
      keys_tmp[dst] = keys[i];
      idx_tmp[dst] = idx[i];
    }
    keys.swap(keys_tmp);
    idx.swap(idx_tmp);
  }
}

std::vector<std::uint32_t> canonical_order(std::span<const std::int64_t> ids, std::size_t n) {
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0U);
  if (ids.empty()) return order;
  std::vector<std::uint64_t> keys(n);
  // Flipping the sign bit maps signed order onto unsigned order.
  for (std::size_t i = 0; i < n; ++i)
    keys[i] = static_cast<std::uint64_t>(ids[i]) ^ (std::uint64_t{1} << 63);
  radix_sort(keys, order);
  return order;
}

CellGrid::CellGrid(std::span<const double> x, std::span<const double> y, std::span<const double> z,
                   std::span<const std::uint32_t> input_order, const double (&lo)[3], double h) {
  const std::size_t n = input_order.size();
  if (n > 0xFFFFFFFEULL) throw std::length_error("fragment search: too many particles");
  std::vector<std::uint64_t> keys(n);
  order_.assign(input_order.begin(), input_order.end());
  const double inv_h = 1.0 / h;
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint32_t p = order_[k];
    const double c[3] = {(x[p] - lo[0]) * inv_h, (y[p] - lo[1]) * inv_h, (z[p] - lo[2]) * inv_h};
    std::int64_t ic[3];
    for (int d = 0; d < 3; ++d) {
      if (!(c[d] >= 0.0) || c[d] > static_cast<double>(kMaxIndex))
        throw std::runtime_error(
            "fragment search: particles span more than 2^21 cells per axis (or a position is "
            "not finite); use a larger cell_size");
      ic[d] = static_cast<std::int64_t>(c[d]);
    }
    keys[k] = pack(ic[0], ic[1], ic[2]);
  }
  radix_sort(keys, order_);
  cell_of_.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    if (k == 0 || keys[k] != keys[k - 1])
      cells_.push_back({keys[k], static_cast<std::uint32_t>(k), static_cast<std::uint32_t>(k)});
    cells_.back().end = static_cast<std::uint32_t>(k + 1);
    cell_of_[k] = static_cast<std::uint32_t>(cells_.size() - 1);
  }
  std::size_t capacity = 16;
  while (capacity < 2 * cells_.size()) capacity *= 2;
  table_.assign(capacity, 0);
  table_mask_ = capacity - 1;
  for (std::size_t c = 0; c < cells_.size(); ++c) {
    std::uint64_t slot = splitmix64(cells_[c].key) & table_mask_;
    while (table_[slot] != 0) slot = (slot + 1) & table_mask_;
    table_[slot] = static_cast<std::uint32_t>(c + 1);
  }
  neighbour_begin_.assign(cells_.size() + 1, 0);
  neighbours_.reserve(cells_.size() * 27);
  for (std::size_t c = 0; c < cells_.size(); ++c) {
    const std::uint64_t key = cells_[c].key;
    const auto ix = static_cast<std::int64_t>(key >> 42);
    const auto iy = static_cast<std::int64_t>((key >> 21) & kMask);
    const auto iz = static_cast<std::int64_t>(key & kMask);
    for (std::int64_t dx = -1; dx <= 1; ++dx)
      for (std::int64_t dy = -1; dy <= 1; ++dy)
        for (std::int64_t dz = -1; dz <= 1; ++dz) {
          const std::int64_t jx = ix + dx, jy = iy + dy, jz = iz + dz;
          if (jx < 0 || jy < 0 || jz < 0 || jx > kMaxIndex || jy > kMaxIndex || jz > kMaxIndex)
            continue;
          const std::int64_t found = find(pack(jx, jy, jz));
          if (found >= 0) neighbours_.push_back(static_cast<std::uint32_t>(found));
        }
    neighbour_begin_[c + 1] = static_cast<std::uint32_t>(neighbours_.size());
  }
}

std::int64_t CellGrid::find(std::uint64_t key) const {
  std::uint64_t slot = splitmix64(key) & table_mask_;
  while (true) {
    const std::uint32_t entry = table_[slot];
    if (entry == 0) return -1;
    if (cells_[entry - 1].key == key) return static_cast<std::int64_t>(entry - 1);
    slot = (slot + 1) & table_mask_;
  }
}

}  // namespace shatter::fracture
