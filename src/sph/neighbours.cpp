#include "shatter/sph/neighbours.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <new>
#include <numeric>
#include <stdexcept>

#if defined(__AVX512F__)
#include <immintrin.h>
#endif

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
void rows_around(const std::vector<std::uint64_t>& cell_key,
                 const std::vector<std::uint32_t>& cell_start, std::uint64_t key, Rows& rows) {
  rows.count = 0;
  rows.candidates = 0;
  for_rows(cell_key, cell_start, key, 1, [&](std::uint32_t s0, std::uint32_t s1) {
    rows.s0[rows.count] = s0;
    rows.s1[rows.count] = s1;
    rows.candidates += s1 - s0;
    ++rows.count;
  });
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

// Ascending order of a list that is mostly sorted: insertion, or std::sort once the moves
// exceed 8 per entry. The same result either way.
void sort_nearly_sorted(std::uint32_t* list, std::size_t m) {
  std::size_t budget = 8 * m;
  for (std::size_t a = 1; a < m; ++a) {
    const std::uint32_t v = list[a];
    std::size_t b = a;
    for (; b > 0 && list[b - 1] > v && budget > 0; --b, --budget) list[b] = list[b - 1];
    list[b] = v;
    if (budget == 0) {
      std::sort(list, list + m);
      return;
    }
  }
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
  wide_pairs(at, n, n_lists, skin);
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
  std::vector<std::uint32_t> runs;  // a wide point's rows (none in most chunks: no allocation)
  const std::size_t first = c * kGrain, last = std::min(n_lists, (c + 1) * kGrain);
  // The pairs the wide points listed for this chunk's points (ascending by point).
  auto pair = std::lower_bound(wide_pairs_.begin(), wide_pairs_.end(), std::uint64_t{first} << 32);
  for (std::size_t i = first; i < last; ++i) {
    const double xi = at.x[i], yi = at.y[i], zi = at.z[i], hi_ = at.h[i];
    const bool wide = hi_ > split_;
    std::size_t candidates = 0, from_wide = 0;
    if (wide) {
      candidates = wide_candidates(i, hi_, skin, runs);
    } else {
      const std::uint64_t key = cell_key_[cell_[i]];
      if (!have_rows || key != rows_key) {
        rows_around(cell_key_, cell_start_, key, rows);
        rows_key = key;
        have_rows = true;
      }
      candidates = rows.candidates;
      while (pair + static_cast<std::ptrdiff_t>(from_wide) != wide_pairs_.end() &&
             (pair[static_cast<std::ptrdiff_t>(from_wide)] >> 32) == i) {
        ++from_wide;
      }
    }
    if (buf.size() < used + candidates + from_wide) {
      // The buffers hold the lists for good: grow by an eighth (not the doubling of resize),
      // so that they hold little more than the lists.
      buf.reserve(std::max(buf.size() + buf.size() / 8, used + candidates + from_wide));
      buf.resize(buf.capacity());
    }
    std::uint32_t* out = buf.data() + used;
    std::size_t m = 0;
    // A candidate is written, then counted if within reach: no branch. A point of h <= split
    // takes only the points of h <= split from its 27 cells (all of those within reach are
    // there); the wide ones within its reach come from wide_pairs_.
    const auto take = [&](std::uint32_t s0, std::uint32_t s1, double cap) {
      std::uint32_t t = s0;
#if defined(__AVX512F__) && defined(__AVX512VL__) && defined(__FMA__)
      // 8 candidates at a time, from the columns in cell order (plain loads, no gathers): the
      // same test as the scalar loop (distance2 with FMA, the same sums), the points within
      // reach compressed in a register and stored as 8 lanes at the list's end (the lanes past
      // them stay inside this run's room for all candidates).
      const __m512d XI = _mm512_set1_pd(xi), YI = _mm512_set1_pd(yi), ZI = _mm512_set1_pd(zi),
                    HI = _mm512_set1_pd(hi_), SKIN = _mm512_set1_pd(skin),
                    CAP = _mm512_set1_pd(cap);
      const __m256i I = _mm256_set1_epi32(static_cast<int>(i));
      for (; t + 8 <= s1; t += 8) {
        const __m512d dx = _mm512_sub_pd(XI, _mm512_loadu_pd(xs_ + t));
        const __m512d dy = _mm512_sub_pd(YI, _mm512_loadu_pd(ys_ + t));
        const __m512d dz = _mm512_sub_pd(ZI, _mm512_loadu_pd(zs_ + t));
        const __m512d hj = _mm512_loadu_pd(hs_ + t);
        const __m512d reach = _mm512_add_pd(_mm512_add_pd(HI, hj), SKIN);
        const __m512d r2 = _mm512_fmadd_pd(dz, dz, _mm512_fmadd_pd(dx, dx, _mm512_mul_pd(dy, dy)));
        const __m256i idx =
            _mm256_loadu_si256(reinterpret_cast<const __m256i*>(sorted_.data() + t));
        const __mmask8 take8 = _mm512_cmp_pd_mask(r2, _mm512_mul_pd(reach, reach), _CMP_LT_OQ) &
                               _mm512_cmp_pd_mask(hj, CAP, _CMP_LE_OQ) &
                               _mm256_cmpneq_epi32_mask(idx, I);
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + m),
                            _mm256_maskz_compress_epi32(take8, idx));
        m += static_cast<std::size_t>(__builtin_popcount(take8));
      }
#endif
      for (; t < s1; ++t) {
        const double dx = xi - xs_[t], dy = yi - ys_[t], dz = zi - zs_[t];
        const double reach = hi_ + hs_[t] + skin;  // 2 h_ij (+ the skin)
        out[m] = sorted_[t];
        // The compaction's own expression (kernels/sph/gather.hpp).
        m += (kernels::sph::distance2(dx, dy, dz) < reach * reach) & (hs_[t] <= cap) &
                     (sorted_[t] != i)
                 ? 1
                 : 0;
      }
    };
    if (wide) {
      for (std::size_t r = 0; r + 1 < runs.size(); r += 2) {
        take(runs[r], runs[r + 1], hmax_);
      }
    } else {
      for (std::uint32_t row = 0; row < rows.count; ++row) take(rows.s0[row], rows.s1[row], split_);
      for (std::size_t k = 0; k < from_wide; ++k) {
        out[m++] = static_cast<std::uint32_t>(pair[static_cast<std::ptrdiff_t>(k)]);
      }
      pair += static_cast<std::ptrdiff_t>(from_wide);
    }
    // Ascending index: the canonical order, whatever the cells and skin. Points re-ordered by
    // cell meet their candidates mostly in that order already (rows in key order, points of a
    // cell in index order), so an insertion sort (no partitioning: std::sort's introsort took
    // ~1.3 % of the laboratory impact) that hands over to std::sort after 8 moves per entry,
    // for lists far from sorted (no re-order).
    sort_nearly_sorted(out, m);
    offsets_[i + 1] = m;
    used += m;
  }
}

// The rows of a wide point p's stencil into `runs` (pairs of slots), and their point count:
// every cell within h_p + max h + skin of p's cell along each axis.
std::size_t NeighbourSearch::wide_candidates(std::size_t p, double hp, double skin,
                                             std::vector<std::uint32_t>& runs) const {
  // floor + 1 >= ceil: one more cell where the reach is a whole number of cells.
  const auto m = static_cast<std::uint64_t>((hp + hmax_ + skin) / cell_size_) + 1;
  runs.clear();
  std::size_t count = 0;
  for_rows(cell_key_, cell_start_, cell_key_[cell_[p]], m, [&](std::uint32_t s0, std::uint32_t s1) {
    runs.push_back(s0);
    runs.push_back(s1);
    count += s1 - s0;
  });
  return count;
}

// For each wide point p (h_p > split_; images included, which have no list), the points i <
// n_lists of h_i <= split_ within h_i + h_p + skin, as (i, p) ascending in wide_pairs_: the pairs
// that i's 27 cells may not hold. The pair test is the lists' own, symmetric in i and p.
void NeighbourSearch::wide_pairs(const Coordinates& at, std::size_t n, std::size_t n_lists,
                                 double skin) {
  wide_.clear();
  wide_pairs_.clear();
  if (!(split_ < hmax_)) return;
  for (std::size_t p = 0; p < n; ++p) {
    if (at.h[p] > split_) wide_.push_back(static_cast<std::uint32_t>(p));
  }
  constexpr std::size_t kBlock = 64;
  std::vector<std::vector<std::uint64_t>> found((wide_.size() + kBlock - 1) / kBlock);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, found.size(), 1),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      std::vector<std::uint32_t> runs;
                      for (std::size_t b = r.begin(); b < r.end(); ++b) {
                        for (std::size_t k = b * kBlock;
                             k < std::min(wide_.size(), (b + 1) * kBlock); ++k) {
                          const std::uint32_t p = wide_[k];
                          const double xp = at.x[p], yp = at.y[p], zp = at.z[p], hp = at.h[p];
                          wide_candidates(p, hp, skin, runs);
                          for (std::size_t q = 0; q + 1 < runs.size(); q += 2) {
                            for (std::uint32_t t = runs[q]; t < runs[q + 1]; ++t) {
                              const std::uint32_t i = sorted_[t];
                              if (i >= n_lists || hs_[t] > split_) continue;
                              const double dx = xs_[t] - xp, dy = ys_[t] - yp, dz = zs_[t] - zp;
                              const double reach = hs_[t] + hp + skin;
                              if (kernels::sph::distance2(dx, dy, dz) < reach * reach) {
                                found[b].push_back((std::uint64_t{i} << 32) | p);
                              }
                            }
                          }
                        }
                      }
                    });
  for (const auto& f : found) wide_pairs_.insert(wide_pairs_.end(), f.begin(), f.end());
  // (i, p) pairs are unique: the sorted order does not depend on the blocks' schedule.
  std::sort(wide_pairs_.begin(), wide_pairs_.end());
}

}  // namespace shatter::sph
