// The neighbour lists of a build (NeighbourSearch::make_lists): each point's candidates from the
// rows of cells around it (neighbours.cpp bins the points), the wide points' pairs, the lists in
// ascending index order.
#include <algorithm>
#include <new>

#if defined(__AVX512F__)
#include <immintrin.h>
#endif

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "shatter/sph/neighbours.hpp"
#include "sph/cell_keys.hpp"
#include "sph/gather.hpp"

namespace shatter::sph {
namespace {

using cell_keys::for_rows;
using cell_keys::kGrain;
using cell_keys::Rows;
using cell_keys::rows_around;

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

// The columns in cell order and a point's query against them.
struct SortedColumns {
  const double *x, *y, *z, *h;
  const std::uint32_t* index;  // the point in each slot
};
struct Query {
  double x, y, z, h, skin;
  std::uint32_t self;
};

// Appends to out[m, ...) the points of slots [s0, s1) within reach of q (h_q + h_j + skin) whose
// h <= cap, and returns the new count. A candidate is written, then counted if within reach: no
// branch; out needs room for s1 - s0 more entries (8 more lanes are written past the count).
std::size_t append_within_reach(const SortedColumns& col, const Query& q, std::uint32_t s0,
                                std::uint32_t s1, double cap, std::uint32_t* out, std::size_t m) {
  std::uint32_t t = s0;
#if defined(__AVX512F__) && defined(__AVX512VL__) && defined(__FMA__)
  // 8 candidates at a time, from the columns in cell order (plain loads, no gathers): the
  // same test as the scalar loop (distance2 with FMA, the same sums), the points within
  // reach compressed in a register and stored as 8 lanes at the list's end (the lanes past
  // them stay inside this run's room for all candidates).
  const __m512d XI = _mm512_set1_pd(q.x), YI = _mm512_set1_pd(q.y), ZI = _mm512_set1_pd(q.z),
                HI = _mm512_set1_pd(q.h), SKIN = _mm512_set1_pd(q.skin), CAP = _mm512_set1_pd(cap);
  const __m256i I = _mm256_set1_epi32(static_cast<int>(q.self));
  for (; t + 8 <= s1; t += 8) {
    const __m512d dx = _mm512_sub_pd(XI, _mm512_loadu_pd(col.x + t));
    const __m512d dy = _mm512_sub_pd(YI, _mm512_loadu_pd(col.y + t));
    const __m512d dz = _mm512_sub_pd(ZI, _mm512_loadu_pd(col.z + t));
    const __m512d hj = _mm512_loadu_pd(col.h + t);
    const __m512d reach = _mm512_add_pd(_mm512_add_pd(HI, hj), SKIN);
    const __m512d r2 = _mm512_fmadd_pd(dz, dz, _mm512_fmadd_pd(dx, dx, _mm512_mul_pd(dy, dy)));
    const __m256i idx = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(col.index + t));
    const __mmask8 take8 = _mm512_cmp_pd_mask(r2, _mm512_mul_pd(reach, reach), _CMP_LT_OQ) &
                           _mm512_cmp_pd_mask(hj, CAP, _CMP_LE_OQ) &
                           _mm256_cmpneq_epi32_mask(idx, I);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + m),
                        _mm256_maskz_compress_epi32(take8, idx));
    m += static_cast<std::size_t>(__builtin_popcount(take8));
  }
#endif
  for (; t < s1; ++t) {
    const double dx = q.x - col.x[t], dy = q.y - col.y[t], dz = q.z - col.z[t];
    const double reach = q.h + col.h[t] + q.skin;  // 2 h_ij (+ the skin)
    out[m] = col.index[t];
    // The compaction's own expression (kernels/sph/gather.hpp).
    m += (kernels::sph::distance2(dx, dy, dz) < reach * reach) & (col.h[t] <= cap) &
                 (col.index[t] != q.self)
             ? 1
             : 0;
  }
  return m;
}

}  // namespace

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
    // A point of h <= split takes only the points of h <= split from its 27 cells (all of those
    // within reach are there); the wide ones within its reach come from wide_pairs_.
    const SortedColumns col{xs_, ys_, zs_, hs_, sorted_.data()};
    const Query q{xi, yi, zi, hi_, skin, static_cast<std::uint32_t>(i)};
    const auto take = [&](std::uint32_t s0, std::uint32_t s1, double cap) {
      m = append_within_reach(col, q, s0, s1, cap, out, m);
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
