#pragma once
// Neighbour search for SPH with variable smoothing lengths (issue 10 item 5): sorted cell lists.
// Points are binned into cubic cells of edge 2 max(h) (the largest support h_i + h_j; in a build
// where the largest h is over 1.2 times the 99th percentile, 2 x that percentile, and the few
// wider points search wider stencils: split_ below) and sorted by cell key (as the MPM engine sorts
// by grid block). Only occupied cells exist: a sorted array of keys, looked up by binary search,
// one interval per row of three cells, so ejecta flying far from the body cost nothing (a dense
// cell array over the bounding box would either grow with it or need coarser cells). Each point
// gathers its neighbours from the 27 cells around its own (a wide point from more). j is a
// neighbour of i when j != i and |x_i - x_j| < h_i + h_j + skin (2 h_ij is the support of W(r,
// h_ij); the skin, 0 by default, lets the lists serve several steps, Verlet lists). Each list is in
// ascending index order: canonical, independent of the cells, the skin and the thread count, so a
// gather over a list with a skin (whose extra entries the forces pass compacts away) sums the same
// terms in the same order as over a fresh list without one, and the sums have the same bits (a
// caller may re-arrange a list in place: rearrange()). Buffers are reused: a build allocates only
// while a buffer grows past its largest size so far (the lists are gathered in one pass per chunk
// of points into per-chunk buffers, where they stay), so a run stops allocating once its neighbour
// counts stop growing.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace shatter::sph {

class NeighbourSearch {
 public:
  // Builds the lists for n points. Positions and h must be finite; h > 0.
  void build(const double* x, const double* y, const double* z, const double* h, std::size_t n);
  // As above, but lists only for points 0 .. n_lists - 1; points n_lists .. n - 1 are found as
  // neighbours and have no list of their own (the mirror particles of the SPH boundaries).
  void build(const double* x, const double* y, const double* z, const double* h, std::size_t n,
             std::size_t n_lists, double skin = 0.0);

  // Only the binning of a build without a skin, always with cells of edge 2 max h: cells() and
  // cell_size() as a build without wide points would give them, no new lists. For re-ordering
  // particles by cell without building lists that the re-order makes stale. The last build's lists
  // are kept as they were (lists(), of(), offset() still answer for them), for permute(); size()
  // and cells() are the bin's.
  void bin(const double* x, const double* y, const double* z, const double* h, std::size_t n);

  // The last build's lists carried through a renumbering of the points (a re-order of the
  // particles in memory), without a build: new list k is old list from[k] (from.size() =
  // lists(), a permutation), and every entry, an old point index p, becomes to[p] (to: a
  // permutation of the points the lists number, those of the last build). Each list is then sorted
  // into ascending index order again, so it is exactly the list a build at the same positions, h
  // and skin gives when the renumbered points are the same set (the order does not depend on the
  // cells or on the list's storage). The lists stay in their buffers (only where each one starts
  // moves), so nothing is copied and nothing allocated beyond 16 B per list; offset() is the new
  // numbering's. cells() is left as it was (the last bin's, before the renumbering).
  // With `sort_first` (one count per new list, at most its length), only the first
  // sort_first[k] entries of list k are sorted, the others left in an order of no meaning (for a
  // caller that re-arranged the lists: rearrange()).
  void permute(std::span<const std::uint32_t> from, std::span<const std::uint32_t> to,
               std::span<const std::uint32_t> sort_first = {});

  // Storage the caller lends for the sort buffers of the next build or bin (the points' cell
  // keys, 16 B per point, then in the same storage their positions and h in cell order, 32 B;
  // free again when it returns), at least sort_doubles(n) doubles for n points. The search then
  // holds none of its own; with too little (or none: the default) it uses its own buffers.
  void lend(std::span<double> storage) { lent_ = storage; }
  static std::size_t sort_doubles(std::size_t n) { return 4 * n; }

  // Points in the last build, and those with a list.
  std::size_t size() const { return n_; }
  std::size_t lists() const { return lists_; }
  // Neighbours of point i < lists() (i itself excluded).
  std::span<const std::uint32_t> of(std::size_t i) const { return {begin_[i], count(i)}; }
  const std::uint32_t* begin_of(std::size_t i) const { return begin_[i]; }
  // Point i's list for re-arranging in place, the same entries in another order (the SPH solver
  // moves the pairs within support to the front: kernels::sph::partition_within_support). of()
  // then gives them in that order; a build or permute() makes the lists ascending again.
  std::uint32_t* rearrange(std::size_t i) { return const_cast<std::uint32_t*>(begin_[i]); }
  std::size_t count(std::size_t i) const { return offsets_[i + 1] - offsets_[i]; }
  // Index of point i's first entry in the lists concatenated in index order (for per-pair
  // data, which the passes then stream in their own order).
  std::size_t offset(std::size_t i) const { return offsets_[i]; }
  // Total number of (ordered) pairs: sum over i of count(i).
  std::size_t pairs() const { return offsets_.empty() ? 0 : offsets_[lists_]; }
  // Cell of each point in the last build, numbered in key order (for re-ordering particles in
  // memory by cell).
  std::span<const std::uint32_t> cells() const { return {cell_.data(), n_}; }
  // Cell edge used by the last build or bin: 2 max h, or 2 split_ for a build with wide points
  // (doubled only for a cloud wider than 2^21 cells).
  double cell_size() const { return cell_size_; }
  // Number of occupied cells in the last build.
  std::size_t cell_count() const { return cell_key_.size(); }
  // Bytes held by the search structures.
  std::size_t bytes() const;

 private:
  // The cells, sorted points and (n_lists + 1) offsets' first entry; false for no points.
  // With keep_lists (bin), the lists' offsets, starts and count are left as they were.
  bool sort_by_cell(const double* x, const double* y, const double* z, const double* h,
                    std::size_t n, std::size_t n_lists, double skin, bool keep_lists = false);
  void make_lists(const double* x, const double* y, const double* z, const double* h, std::size_t n,
                  std::size_t n_lists, double skin);
  // One chunk of make_lists: the lists of the points of chunk c.
  struct Coordinates {
    const double *x, *y, *z, *h;
  };
  void gather_chunk(std::size_t c, const Coordinates& at, std::size_t n_lists, double skin);
  // The wide points' stencils and the pairs they list for the others (see split_).
  std::size_t wide_candidates(std::size_t p, double hp, double skin,
                              std::vector<std::uint32_t>& runs) const;
  void wide_pairs(const Coordinates& at, std::size_t n, std::size_t n_lists, double skin);

  struct KeyIndex {
    std::uint64_t key;
    std::uint32_t index;
    bool operator<(const KeyIndex& o) const {
      return key < o.key || (key == o.key && index < o.index);
    }
  };
  std::size_t n_ = 0;
  std::size_t lists_ = 0;
  std::size_t listed_ = 0;  // points the lists' entries number (n of the last build or permute)
  double cell_size_ = 0.0;
  // A build's cells have edge 2 split_ + skin (split_ <= the largest h, hmax_): a point of h <=
  // split_ finds every neighbour of h <= split_ in the 27 cells around its own; a wide point (h
  // > split_, few) searches the cells within h + hmax_ + skin of its own and lists, for each
  // point of h <= split_ within reach, the pair in wide_pairs_ ((i << 32) | p, ascending), which
  // that point's list takes. A bin's split_ is hmax_.
  double split_ = 0.0, hmax_ = 0.0;
  std::vector<std::uint32_t> wide_;
  std::vector<std::uint64_t> wide_pairs_;
  // The sort buffers, in lent_ or own_ (sort_storage): (cell key, point) sorted, during a bin or
  // build; then, in the same storage, positions and h in sorted order, during a build.
  double* sort_storage(std::size_t n);
  std::span<double> lent_;
  std::vector<double> own_;
  KeyIndex* keyed_ = nullptr;
  double *xs_ = nullptr, *ys_ = nullptr, *zs_ = nullptr, *hs_ = nullptr;
  std::vector<std::uint64_t> cell_key_;    // occupied cells' keys, ascending
  std::vector<std::uint32_t> cell_;        // occupied-cell index of each point
  std::vector<std::uint32_t> cell_start_;  // first sorted slot of each occupied cell (+1 sentinel)
  std::vector<std::uint32_t> sorted_;      // point indices sorted by cell, then index
  std::vector<std::size_t> offsets_;       // CSR offsets of the lists in index order (n + 1)
  // Point i's list, in its chunk's buffer (the lists stay there: no copy into one array).
  std::vector<const std::uint32_t*> begin_;
  std::vector<std::vector<std::uint32_t>> chunk_list_;  // per chunk of points, reused
};

}  // namespace shatter::sph
