// The neighbour search's cell keys and their rows of cells, shared by the binning
// (neighbours.cpp) and the list builds (neighbour_lists.cpp). Private to src/sph.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace shatter::sph::cell_keys {

// Fixed grain (never derived from the thread count); the lists do not depend on it anyway.
constexpr std::size_t kGrain = 512;

// A cell key packs the three integer cell coordinates, 21 bits each, z major: cells that are
// neighbours along x have consecutive keys, so a row of three cells is one key interval.
constexpr int kBits = 21;
constexpr std::uint64_t kAxisCells = std::uint64_t{1} << kBits;
constexpr std::uint64_t key_of(std::uint64_t k0, std::uint64_t k1, std::uint64_t k2) {
  return (k2 << (2 * kBits)) | (k1 << kBits) | k0;
}

// Visits the runs of sorted slots [s0, s1) of the rows of 2 m + 1 cells along x around cell
// `key`, within m cells of it along y and z (up to (2 m + 1)^2 rows): every point within m cell
// edges of the cell along each axis.
template <class F>
void for_rows(const std::vector<std::uint64_t>& cell_key,
              const std::vector<std::uint32_t>& cell_start, std::uint64_t key, std::uint64_t m,
              F&& visit) {
  const std::uint64_t mask = kAxisCells - 1;
  const std::uint64_t k0 = key & mask, k1 = (key >> kBits) & mask, k2 = key >> (2 * kBits);
  for (std::uint64_t c2 = k2 > m ? k2 - m : 0; c2 <= std::min(k2 + m, mask); ++c2) {
    for (std::uint64_t c1 = k1 > m ? k1 - m : 0; c1 <= std::min(k1 + m, mask); ++c1) {
      // The row's cells x - m .. x + m are one key interval, one run of sorted points.
      const std::uint64_t first = key_of(k0 > m ? k0 - m : 0, c1, c2);
      const std::uint64_t last = key_of(std::min(k0 + m, mask), c1, c2);
      const auto a = std::lower_bound(cell_key.begin(), cell_key.end(), first);
      auto b = a;
      while (b != cell_key.end() && *b <= last) ++b;
      if (a == b) continue;
      visit(cell_start[static_cast<std::size_t>(a - cell_key.begin())],
            cell_start[static_cast<std::size_t>(b - cell_key.begin())]);
    }
  }
}

// The sorted slots [s0, s1) of the (up to) nine rows of three cells around cell `key`.
struct Rows {
  std::uint32_t count = 0;
  std::uint32_t s0[9], s1[9];
  std::size_t candidates = 0;
};
inline void rows_around(const std::vector<std::uint64_t>& cell_key,
                        const std::vector<std::uint32_t>& cell_start, std::uint64_t key,
                        Rows& rows) {
  rows.count = 0;
  rows.candidates = 0;
  for_rows(cell_key, cell_start, key, 1, [&](std::uint32_t s0, std::uint32_t s1) {
    rows.s0[rows.count] = s0;
    rows.s1[rows.count] = s1;
    rows.candidates += s1 - s0;
    ++rows.count;
  });
}

}  // namespace shatter::sph::cell_keys
