#include "shatter/sph/neighbours.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <new>
#include <numeric>
#include <stdexcept>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include "sph/cell_keys.hpp"

namespace shatter::sph {
namespace {

using cell_keys::kAxisCells;
using cell_keys::key_of;
using cell_keys::kGrain;

void check_arguments(std::size_t n, std::size_t n_lists, double skin) {
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
}

// Bounding box and largest h of n >= 1 points (min/max are exact: any order gives the same
// result).
struct Box {
  double lo[3], hi[3];
  double hmax;
};
Box bounding_box(const double* x, const double* y, const double* z, const double* h,
                 std::size_t n) {
  Box b{{x[0], y[0], z[0]}, {x[0], y[0], z[0]}, h[0]};
  for (std::size_t p = 0; p < n; ++p) {
    const double c[3] = {x[p], y[p], z[p]};
    for (int d = 0; d < 3; ++d) {
      b.lo[d] = std::min(b.lo[d], c[d]);
      b.hi[d] = std::max(b.hi[d], c[d]);
    }
    b.hmax = std::max(b.hmax, h[p]);
  }
  if (!(b.hmax > 0.0) || !std::isfinite(b.hmax)) {
    throw std::invalid_argument(fmt::format("neighbour search: largest h is {}", b.hmax));
  }
  return b;
}

// Cell edge: the largest support plus the skin, 2 hmax + skin >= h_i + h_j + skin, so the 27
// cells around a point hold all its neighbours. Only occupied cells exist (sorted keys), so
// debris flying far costs nothing; only a cloud wider than 2^21 cells on an axis gets larger
// cells.
double cell_edge(const Box& b, double hcell, double skin) {
  double cs = 2.0 * hcell + skin;
  for (int d = 0; d < 3; ++d) {
    while ((b.hi[d] - b.lo[d]) / cs >= static_cast<double>(kAxisCells - 2)) cs *= 2.0;
  }
  return cs;
}

// The h up to which a build's points find all their neighbours in the 27 cells around their own
// (a point of larger h, "wide", searches a wider stencil, and the others find it through the
// pairs it lists for them: make_lists). With one edge for all, 2 max h, a few points of large h
// (in the SPH solver, the fast particles' large Verlet skins and the expanding ejecta's h) made
// every point's 27 cells hold ~20 times its neighbours in the laboratory impact, 3 times in a
// uniform cube (docs/performance.md, session 22). The split is the largest h but one per cent of
// a sample of every 8th point, where the largest h is over 1.2 times it; otherwise the largest h
// (no wide points). A function of the values alone: the same on any thread count.
constexpr std::size_t kSplitStride = 8;
constexpr double kSplitQuantile = 0.99, kSplitRatio = 1.2;
double split_h(const double* h, std::size_t n, double hmax) {
  std::vector<double> sample;
  sample.reserve(n / kSplitStride + 1);
  for (std::size_t p = 0; p < n; p += kSplitStride) sample.push_back(h[p]);
  const auto k = static_cast<std::size_t>(kSplitQuantile * static_cast<double>(sample.size() - 1));
  std::nth_element(sample.begin(), sample.begin() + static_cast<std::ptrdiff_t>(k), sample.end());
  const double q = sample[k];
  return hmax > kSplitRatio * q ? q : hmax;
}

}  // namespace

std::size_t NeighbourSearch::bytes() const {
  return sizeof(std::uint32_t) * (cell_.capacity() + cell_start_.capacity() + sorted_.capacity()) +
         sizeof(std::size_t) * offsets_.capacity() +
         sizeof(const std::uint32_t*) * begin_.capacity() +
         sizeof(std::uint64_t) * (cell_key_.capacity() + wide_pairs_.capacity()) +
         sizeof(std::uint32_t) * wide_.capacity() + sizeof(double) * own_.capacity() +
         std::accumulate(chunk_list_.begin(), chunk_list_.end(), std::size_t{0},
                         [](std::size_t a, const std::vector<std::uint32_t>& v) {
                           return a + sizeof(std::uint32_t) * v.capacity();
                         });
}

double* NeighbourSearch::sort_storage(std::size_t n) {
  static_assert(sizeof(KeyIndex) <= 4 * sizeof(double) && alignof(KeyIndex) <= alignof(double));
  const std::size_t need = sort_doubles(n);
  if (lent_.size() >= need) return lent_.data();
  if (own_.size() < need) own_.resize(need);
  return own_.data();
}

void NeighbourSearch::build(const double* x, const double* y, const double* z, const double* h,
                            std::size_t n) {
  build(x, y, z, h, n, n, 0.0);
}

void NeighbourSearch::bin(const double* x, const double* y, const double* z, const double* h,
                          std::size_t n) {
  sort_by_cell(x, y, z, h, n, 0, 0.0, true);
  lent_ = {};
}

void NeighbourSearch::permute(std::span<const std::uint32_t> from,
                              std::span<const std::uint32_t> to,
                              std::span<const std::uint32_t> sort_first) {
  if (from.size() != lists_) {
    throw std::invalid_argument(fmt::format(
        "neighbour search: a permutation of {} lists for {} lists", from.size(), lists_));
  }
  if (to.size() != listed_) {
    throw std::invalid_argument(
        fmt::format("neighbour search: {} points renumbered for {} lists", to.size(), lists_));
  }
  std::vector<const std::uint32_t*> begin(lists_);
  std::vector<std::size_t> offsets(lists_ + 1);
  offsets[0] = 0;
  for (std::size_t k = 0; k < lists_; ++k) {
    const std::size_t old = from[k];
    begin[k] = begin_[old];
    offsets[k + 1] = offsets[k] + (offsets_[old + 1] - offsets_[old]);
  }
  begin_.swap(begin);
  offsets_.swap(offsets);
  n_ = to.size();
  // A bijection keeps every entry below listed_.
  // Each list is in its own slots (those of the old list it was), so the lists are rewritten
  // in place, in parallel, each on its own.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, lists_, kGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t k = r.begin(); k < r.end(); ++k) {
                        // The buffers are written through the search's own pointers.
                        auto* list = const_cast<std::uint32_t*>(begin_[k]);
                        const std::size_t m = offsets_[k + 1] - offsets_[k];
                        for (std::size_t e = 0; e < m; ++e) list[e] = to[list[e]];
                        const std::size_t sort =
                            sort_first.empty() ? m : std::min<std::size_t>(m, sort_first[k]);
                        if (!std::is_sorted(list, list + sort)) std::sort(list, list + sort);
                      }
                    });
}

void NeighbourSearch::build(const double* x, const double* y, const double* z, const double* h,
                            std::size_t n, std::size_t n_lists, double skin) {
  if (sort_by_cell(x, y, z, h, n, n_lists, skin)) make_lists(x, y, z, h, n, n_lists, skin);
  lent_ = {};
}

bool NeighbourSearch::sort_by_cell(const double* x, const double* y, const double* z,
                                   const double* h, std::size_t n, std::size_t n_lists, double skin,
                                   bool keep_lists) {
  check_arguments(n, n_lists, skin);
  n_ = n;
  cell_.resize(n);
  sorted_.resize(n);
  keyed_ = reinterpret_cast<KeyIndex*>(sort_storage(n));
  if (!keep_lists) {
    lists_ = n_lists;
    listed_ = n;
    offsets_.resize(n_lists + 1);
    offsets_[0] = 0;
    begin_.resize(n_lists);
  }
  cell_key_.clear();
  cell_start_.clear();
  if (n == 0) {
    cell_start_.push_back(0);
    return false;
  }

  const Box box = bounding_box(x, y, z, h, n);
  const double* lo = box.lo;
  hmax_ = box.hmax;
  split_ = keep_lists || n_lists == 0 ? box.hmax : split_h(h, n, box.hmax);
  cell_size_ = cell_edge(box, split_, skin);
  const double inv = 1.0 / cell_size_;

  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t p = r.begin(); p < r.end(); ++p) {
          const double c[3] = {x[p], y[p], z[p]};
          std::uint64_t k[3];
          for (int d = 0; d < 3; ++d) {
            k[d] = std::min(static_cast<std::uint64_t>((c[d] - lo[d]) * inv), kAxisCells - 1);
          }
          new (keyed_ + p) KeyIndex{key_of(k[0], k[1], k[2]), static_cast<std::uint32_t>(p)};
        }
      });
  // (key, index) pairs are unique, so the sorted order is the same whatever the sort's
  // schedule: points of one cell in ascending index order.
  tbb::parallel_sort(keyed_, keyed_ + n);
  for (std::size_t s = 0; s < n; ++s) {
    sorted_[s] = keyed_[s].index;
    if (s == 0 || keyed_[s].key != keyed_[s - 1].key) {
      cell_key_.push_back(keyed_[s].key);
      cell_start_.push_back(static_cast<std::uint32_t>(s));
    }
    cell_[keyed_[s].index] = static_cast<std::uint32_t>(cell_key_.size() - 1);
  }
  cell_start_.push_back(static_cast<std::uint32_t>(n));
  return true;
}

}  // namespace shatter::sph
