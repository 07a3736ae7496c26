#include "shatter/sph/neighbours.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

namespace shatter::sph {
namespace {

// Fixed grain (never derived from the thread count); the lists do not depend on it anyway.
constexpr std::size_t kGrain = 512;

// A cell key packs the three integer cell coordinates, 21 bits each, z major: cells that are
// neighbours along x have consecutive keys, so a row of three cells is one key interval.
constexpr int kBits = 21;
constexpr std::uint64_t kAxisCells = std::uint64_t{1} << kBits;
constexpr std::uint64_t key_of(std::uint64_t k0, std::uint64_t k1, std::uint64_t k2) {
  return (k2 << (2 * kBits)) | (k1 << kBits) | k0;
}

}  // namespace

std::size_t NeighbourSearch::bytes() const {
  return sizeof(std::uint32_t) *
             (cell_.capacity() + cell_start_.capacity() + sorted_.capacity() + list_.capacity()) +
         sizeof(std::size_t) * offsets_.capacity() + sizeof(std::uint64_t) * cell_key_.capacity() +
         sizeof(KeyIndex) * keyed_.capacity() +
         std::accumulate(chunk_list_.begin(), chunk_list_.end(), std::size_t{0},
                         [](std::size_t a, const std::vector<std::uint32_t>& v) {
                           return a + sizeof(std::uint32_t) * v.capacity();
                         });
}

void NeighbourSearch::build(const double* x, const double* y, const double* z, const double* h,
                            std::size_t n) {
  build(x, y, z, h, n, n, 0.0);
}

void NeighbourSearch::build(const double* x, const double* y, const double* z, const double* h,
                            std::size_t n, std::size_t n_lists, double skin) {
  if (!(skin >= 0.0) || !std::isfinite(skin)) {
    throw std::invalid_argument(fmt::format("neighbour search: skin must be >= 0, got {}", skin));
  }
  if (n >= std::numeric_limits<std::uint32_t>::max()) {
    throw std::invalid_argument(fmt::format("neighbour search: {} points exceed 2^32 - 1", n));
  }
  if (n_lists > n) {
    throw std::invalid_argument(
        fmt::format("neighbour search: lists for {} of only {} points", n_lists, n));
  }
  n_ = n;
  lists_ = n_lists;
  cell_.resize(n);
  sorted_.resize(n);
  keyed_.resize(n);
  offsets_.resize(n_lists + 1);
  offsets_[0] = 0;
  cell_key_.clear();
  cell_start_.clear();
  if (n == 0) {
    cell_start_.push_back(0);
    return;
  }

  // Bounding box and largest h (min/max are exact: any order gives the same result).
  double lo[3] = {x[0], y[0], z[0]}, hi[3] = {x[0], y[0], z[0]};
  double hmax = h[0];
  for (std::size_t p = 0; p < n; ++p) {
    const double c[3] = {x[p], y[p], z[p]};
    for (int d = 0; d < 3; ++d) {
      lo[d] = std::min(lo[d], c[d]);
      hi[d] = std::max(hi[d], c[d]);
    }
    hmax = std::max(hmax, h[p]);
  }
  if (!(hmax > 0.0) || !std::isfinite(hmax)) {
    throw std::invalid_argument(fmt::format("neighbour search: largest h is {}", hmax));
  }

  // Cell edge: the largest support plus the skin, 2 hmax + skin >= h_i + h_j + skin, so the 27
  // cells around a point hold all its neighbours. Only occupied cells exist (sorted keys), so
  // debris flying far costs nothing; only a cloud wider than 2^21 cells on an axis gets larger
  // cells.
  double cs = 2.0 * hmax + skin;
  for (int d = 0; d < 3; ++d) {
    while ((hi[d] - lo[d]) / cs >= static_cast<double>(kAxisCells - 2)) cs *= 2.0;
  }
  cell_size_ = cs;
  const double inv = 1.0 / cs;

  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t p = r.begin(); p < r.end(); ++p) {
          const double c[3] = {x[p], y[p], z[p]};
          std::uint64_t k[3];
          for (int d = 0; d < 3; ++d) {
            k[d] = std::min(static_cast<std::uint64_t>((c[d] - lo[d]) * inv), kAxisCells - 1);
          }
          keyed_[p] = {key_of(k[0], k[1], k[2]), static_cast<std::uint32_t>(p)};
        }
      });
  // (key, index) pairs are unique, so the sorted order is the same whatever the sort's
  // schedule: points of one cell in ascending index order.
  tbb::parallel_sort(keyed_.begin(), keyed_.end());
  for (std::size_t s = 0; s < n; ++s) {
    sorted_[s] = keyed_[s].index;
    if (s == 0 || keyed_[s].key != keyed_[s - 1].key) {
      cell_key_.push_back(keyed_[s].key);
      cell_start_.push_back(static_cast<std::uint32_t>(s));
    }
    cell_[keyed_[s].index] = static_cast<std::uint32_t>(cell_key_.size() - 1);
  }
  cell_start_.push_back(static_cast<std::uint32_t>(n));

  // Visits the candidates of point i in the fixed order; calls f(j) for each neighbour.
  auto visit = [&](std::size_t i, auto&& f) {
    const std::uint64_t key = cell_key_[cell_[i]];
    const std::uint64_t mask = kAxisCells - 1;
    const std::uint64_t k0 = key & mask, k1 = (key >> kBits) & mask, k2 = key >> (2 * kBits);
    const double xi = x[i], yi = y[i], zi = z[i], hi_ = h[i];
    for (std::uint64_t c2 = k2 > 0 ? k2 - 1 : 0; c2 <= std::min(k2 + 1, mask); ++c2) {
      for (std::uint64_t c1 = k1 > 0 ? k1 - 1 : 0; c1 <= std::min(k1 + 1, mask); ++c1) {
        // The row's cells x - 1 .. x + 1 are one key interval, one run of sorted points.
        const std::uint64_t first = key_of(k0 > 0 ? k0 - 1 : 0, c1, c2);
        const std::uint64_t last = key_of(std::min(k0 + 1, mask), c1, c2);
        const auto a = std::lower_bound(cell_key_.begin(), cell_key_.end(), first);
        auto b = a;
        while (b != cell_key_.end() && *b <= last) ++b;
        if (a == b) continue;
        const std::uint32_t s0 = cell_start_[static_cast<std::size_t>(a - cell_key_.begin())];
        const std::uint32_t s1 = cell_start_[static_cast<std::size_t>(b - cell_key_.begin())];
        for (std::uint32_t s = s0; s < s1; ++s) {
          const std::uint32_t j = sorted_[s];
          if (j == i) continue;
          const double dx = xi - x[j], dy = yi - y[j], dz = zi - z[j];
          const double reach = hi_ + h[j] + skin;  // 2 h_ij (+ the skin)
          if (dx * dx + dy * dy + dz * dz < reach * reach) f(j);
        }
      }
    }
  };

  // One pass over the candidates: each chunk of kGrain points (in sorted order, so neighbouring
  // points share cache lines) gathers its points' lists into its own buffer, kept between builds;
  // the counts give the offsets, and the buffers are copied into place. The chunks are fixed by
  // n alone, and a list's content does not depend on its chunk, so any thread count gives the
  // same lists.
  const std::size_t chunks = (n + kGrain - 1) / kGrain;
  if (chunk_list_.size() < chunks) chunk_list_.resize(chunks);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks, 1),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t c = r.begin(); c < r.end(); ++c) {
                        std::vector<std::uint32_t>& buf = chunk_list_[c];
                        buf.clear();
                        for (std::size_t s = c * kGrain; s < std::min(n, (c + 1) * kGrain); ++s) {
                          const std::size_t i = sorted_[s];
                          if (i >= n_lists) continue;  // a point that is only a neighbour
                          const std::size_t before = buf.size();
                          visit(i, [&](std::uint32_t j) { buf.push_back(j); });
                          // Ascending index: the canonical order, whatever the cells and skin.
                          std::sort(buf.begin() + static_cast<std::ptrdiff_t>(before), buf.end());
                          offsets_[i + 1] = buf.size() - before;
                        }
                      }
                    });
  for (std::size_t i = 0; i < n_lists; ++i) offsets_[i + 1] += offsets_[i];
  if (list_.size() < offsets_[n_lists]) list_.resize(offsets_[n_lists]);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks, 1),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t c = r.begin(); c < r.end(); ++c) {
                        const std::uint32_t* from = chunk_list_[c].data();
                        for (std::size_t s = c * kGrain; s < std::min(n, (c + 1) * kGrain); ++s) {
                          const std::size_t i = sorted_[s];
                          if (i >= n_lists) continue;
                          const std::size_t k = offsets_[i + 1] - offsets_[i];
                          std::copy(from, from + k, list_.data() + offsets_[i]);
                          from += k;
                        }
                      }
                    });
}

}  // namespace shatter::sph
