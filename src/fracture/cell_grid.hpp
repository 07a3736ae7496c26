#pragma once
// A background cell grid for neighbour search in post-processing (MPM paper Sec. 4.1.2 uses the
// MPM grid for the same purpose). Points are sorted by cell key with a stable radix sort (linear
// in N) and occupied cells are found through an open-addressing hash table, so memory follows the
// occupied cells, not the bounding box, and the layout is deterministic for a given input order.

#include <cstdint>
#include <span>
#include <vector>

namespace shatter::fracture {

// Stable LSD radix sort of idx by keys (16-bit digits, passes with one digit value skipped).
void radix_sort(std::vector<std::uint64_t>& keys, std::vector<std::uint32_t>& idx);

// Particles ordered by id (the canonical order that makes results independent of storage
// order); the identity when ids are absent (empty span).
std::vector<std::uint32_t> canonical_order(std::span<const std::int64_t> ids, std::size_t n);

class CellGrid {
 public:
  struct Cell {
    std::uint64_t key;
    std::uint32_t begin;  // range in sorted order
    std::uint32_t end;
  };

  // Sorts the points taken in `input_order` by cell of size h, origin `lo`. Points in one cell
  // keep their input order.
  CellGrid(std::span<const double> x, std::span<const double> y, std::span<const double> z,
           std::span<const std::uint32_t> input_order, const double (&lo)[3], double h);

  // Point index (into x, y, z) of sorted position k.
  std::span<const std::uint32_t> order() const { return order_; }
  std::span<const Cell> cells() const { return cells_; }
  std::uint32_t cell_of(std::uint32_t k) const { return cell_of_[k]; }

  // Calls f(cell index) for each occupied cell among the 27 around cell c (c included), from a
  // table built once, so the hash is probed per cell, not per point.
  template <class F>
  void for_each_neighbour_cell(std::uint32_t c, F&& f) const {
    for (std::uint32_t i = neighbour_begin_[c]; i < neighbour_begin_[c + 1]; ++i) f(neighbours_[i]);
  }

  static constexpr std::int64_t kMaxIndex = (std::int64_t{1} << 21) - 1;

 private:
  static constexpr std::uint64_t kMask = (std::uint64_t{1} << 21) - 1;
  static std::uint64_t pack(std::int64_t ix, std::int64_t iy, std::int64_t iz) {
    return (static_cast<std::uint64_t>(ix) << 42) | (static_cast<std::uint64_t>(iy) << 21) |
           static_cast<std::uint64_t>(iz);
  }
  std::int64_t find(std::uint64_t key) const;

  std::vector<std::uint32_t> order_;
  std::vector<std::uint32_t> cell_of_;
  std::vector<Cell> cells_;
  std::vector<std::uint32_t> table_;            // cell index + 1; 0 = empty
  std::vector<std::uint32_t> neighbour_begin_;  // CSR offsets into neighbours_, per cell
  std::vector<std::uint32_t> neighbours_;
  std::uint64_t table_mask_ = 0;
};

}  // namespace shatter::fracture
