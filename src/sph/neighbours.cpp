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

#include "sph/gather.hpp"

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

// The sorted slots [s0, s1) of the (up to) nine rows of three cells around cell `key`.
struct Rows {
  std::uint32_t count = 0;
  std::uint32_t s0[9], s1[9];
  std::size_t candidates = 0;
};
void rows_around(const std::vector<std::uint64_t>& cell_key,
                 const std::vector<std::uint32_t>& cell_start, std::uint64_t key, Rows& rows) {
  const std::uint64_t mask = kAxisCells - 1;
  const std::uint64_t k0 = key & mask, k1 = (key >> kBits) & mask, k2 = key >> (2 * kBits);
  rows.count = 0;
  rows.candidates = 0;
  for (std::uint64_t c2 = k2 > 0 ? k2 - 1 : 0; c2 <= std::min(k2 + 1, mask); ++c2) {
    for (std::uint64_t c1 = k1 > 0 ? k1 - 1 : 0; c1 <= std::min(k1 + 1, mask); ++c1) {
      // The row's cells x - 1 .. x + 1 are one key interval, one run of sorted points.
      const std::uint64_t first = key_of(k0 > 0 ? k0 - 1 : 0, c1, c2);
      const std::uint64_t last = key_of(std::min(k0 + 1, mask), c1, c2);
      const auto a = std::lower_bound(cell_key.begin(), cell_key.end(), first);
      auto b = a;
      while (b != cell_key.end() && *b <= last) ++b;
      if (a == b) continue;
      rows.s0[rows.count] = cell_start[static_cast<std::size_t>(a - cell_key.begin())];
      rows.s1[rows.count] = cell_start[static_cast<std::size_t>(b - cell_key.begin())];
      rows.candidates += rows.s1[rows.count] - rows.s0[rows.count];
      ++rows.count;
    }
  }
}

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
double cell_edge(const Box& b, double skin) {
  double cs = 2.0 * b.hmax + skin;
  for (int d = 0; d < 3; ++d) {
    while ((b.hi[d] - b.lo[d]) / cs >= static_cast<double>(kAxisCells - 2)) cs *= 2.0;
  }
  return cs;
}

}  // namespace

std::size_t NeighbourSearch::bytes() const {
  return sizeof(std::uint32_t) * (cell_.capacity() + cell_start_.capacity() + sorted_.capacity()) +
         sizeof(std::size_t) * offsets_.capacity() +
         sizeof(const std::uint32_t*) * begin_.capacity() +
         sizeof(std::uint64_t) * cell_key_.capacity() + sizeof(double) * own_.capacity() +
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
  cell_size_ = cell_edge(box, skin);
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

void NeighbourSearch::make_lists(const double* x, const double* y, const double* z, const double* h,
                                 std::size_t n, std::size_t n_lists, double skin) {
  // The positions and h in sorted order: the candidates of a row of cells are then one
  // contiguous run of each column (no indirection per candidate).
  // They take the storage of the keys, which sort_by_cell has read (sorted_, cell_).
  xs_ = sort_storage(n);
  ys_ = xs_ + n;
  zs_ = ys_ + n;
  hs_ = zs_ + n;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t s = r.begin(); s < r.end(); ++s) {
                        const std::uint32_t p = sorted_[s];
                        new (xs_ + s) double(x[p]);
                        new (ys_ + s) double(y[p]);
                        new (zs_ + s) double(z[p]);
                        new (hs_ + s) double(h[p]);
                      }
                    });

  // One pass over the candidates: each chunk of kGrain points in index order gathers its
  // points' lists into its own buffer, kept between builds, where they stay: the buffers in chunk
  // order are the lists in index order, as the passes read them (a copy into one array would
  // hold every list twice). Points of one cell share their rows, found once per run of such
  // points (all of a cell's points once the particles are re-ordered by cell). Candidates are
  // appended without a branch (written, then counted if within reach), into room for all of
  // them. The chunks are fixed by n_lists alone, and a list's content does not depend on its
  // chunk, so any thread count gives the same lists.
  const std::size_t chunks = (n_lists + kGrain - 1) / kGrain;
  if (chunk_list_.size() < chunks) chunk_list_.resize(chunks);
  const Coordinates at{x, y, z, h};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks, 1),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t c = r.begin(); c < r.end(); ++c) {
                        gather_chunk(c, at, n_lists, skin);
                      }
                    });
  // offsets_ held the counts; each list starts where the one before it in its chunk ended.
  for (std::size_t i = 0; i < n_lists; ++i) {
    const std::size_t m = offsets_[i + 1];
    begin_[i] = i % kGrain == 0 ? chunk_list_[i / kGrain].data()
                                : begin_[i - 1] + (offsets_[i] - offsets_[i - 1]);
    offsets_[i + 1] = offsets_[i] + m;
  }
}

// The lists of points [c kGrain, (c + 1) kGrain) (of those with lists), gathered into chunk c's
// buffer (see make_lists); offsets_[i + 1] = the count of i's list.
void NeighbourSearch::gather_chunk(std::size_t c, const Coordinates& at, std::size_t n_lists,
                                   double skin) {
  std::vector<std::uint32_t>& buf = chunk_list_[c];
  std::size_t used = 0;
  Rows rows;
  std::uint64_t rows_key = 0;
  bool have_rows = false;
  for (std::size_t i = c * kGrain; i < std::min(n_lists, (c + 1) * kGrain); ++i) {
    const std::uint64_t key = cell_key_[cell_[i]];
    if (!have_rows || key != rows_key) {
      rows_around(cell_key_, cell_start_, key, rows);
      rows_key = key;
      have_rows = true;
    }
    if (buf.size() < used + rows.candidates) {
      // The buffers hold the lists for good: grow by an eighth (not the doubling of resize),
      // so that they hold little more than the lists.
      buf.reserve(std::max(buf.size() + buf.size() / 8, used + rows.candidates));
      buf.resize(buf.capacity());
    }
    std::uint32_t* out = buf.data() + used;
    std::size_t m = 0;
    const double xi = at.x[i], yi = at.y[i], zi = at.z[i], hi_ = at.h[i];
    for (std::uint32_t row = 0; row < rows.count; ++row) {
      for (std::uint32_t t = rows.s0[row]; t < rows.s1[row]; ++t) {
        const double dx = xi - xs_[t], dy = yi - ys_[t], dz = zi - zs_[t];
        const double reach = hi_ + hs_[t] + skin;  // 2 h_ij (+ the skin)
        out[m] = sorted_[t];
        // The compaction's own expression (kernels/sph/gather.hpp).
        m += (kernels::sph::distance2(dx, dy, dz) < reach * reach) & (sorted_[t] != i) ? 1 : 0;
      }
    }
    // Ascending index: the canonical order, whatever the cells and skin. Points re-ordered by
    // cell meet their candidates mostly in that order already (rows in key order, points of a
    // cell in index order), and a sorted list skips the sort.
    if (!std::is_sorted(out, out + m)) std::sort(out, out + m);
    offsets_[i + 1] = m;
    used += m;
  }
}

}  // namespace shatter::sph
