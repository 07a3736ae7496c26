#include "shatter/sph/neighbours.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace shatter::sph {
namespace {

// Fixed grain (never derived from the thread count); the lists do not depend on it anyway.
constexpr std::size_t kGrain = 512;

}  // namespace

std::size_t NeighbourSearch::bytes() const {
  return sizeof(std::uint32_t) *
             (cell_.capacity() + cell_start_.capacity() + sorted_.capacity() + list_.capacity()) +
         sizeof(std::size_t) * offsets_.capacity();
}

void NeighbourSearch::build(const double* x, const double* y, const double* z, const double* h,
                            std::size_t n) {
  if (n >= std::numeric_limits<std::uint32_t>::max()) {
    throw std::invalid_argument(fmt::format("neighbour search: {} points exceed 2^32 - 1", n));
  }
  n_ = n;
  cell_.resize(n);
  sorted_.resize(n);
  offsets_.resize(n + 1);
  offsets_[0] = 0;
  if (n == 0) {
    cell_start_.assign(1, 0);
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

  // Cell edge: the largest support, 2 hmax >= h_i + h_j, so the 27 cells around a point hold
  // all its neighbours. Grown (by 2^(1/3) per try) while the dense cell array would be too big.
  double cs = 2.0 * hmax;
  std::size_t dims[3] = {1, 1, 1};
  const double cap = static_cast<double>(kMaxCellsPerPoint * n + 64);
  for (;;) {
    double cells = 1.0;
    for (int d = 0; d < 3; ++d) cells *= std::floor((hi[d] - lo[d]) / cs) + 1.0;
    if (cells <= cap) break;
    cs *= 1.2599210498948732;
  }
  for (int d = 0; d < 3; ++d) dims[d] = static_cast<std::size_t>((hi[d] - lo[d]) / cs) + 1;
  cell_size_ = cs;
  const std::size_t ncell = dims[0] * dims[1] * dims[2];
  const double inv = 1.0 / cs;

  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t p = r.begin(); p < r.end(); ++p) {
          const double c[3] = {x[p], y[p], z[p]};
          std::size_t k[3];
          for (int d = 0; d < 3; ++d) {
            k[d] = std::min(static_cast<std::size_t>((c[d] - lo[d]) * inv), dims[d] - 1);
          }
          cell_[p] = static_cast<std::uint32_t>((k[2] * dims[1] + k[1]) * dims[0] + k[0]);
        }
      });

  // Stable counting sort by cell (points of one cell stay in ascending index order).
  cell_start_.assign(ncell + 1, 0);
  for (std::size_t p = 0; p < n; ++p) ++cell_start_[cell_[p] + 1];
  for (std::size_t c = 0; c < ncell; ++c) cell_start_[c + 1] += cell_start_[c];
  // Fill, advancing each cell's start to its end; then shift the starts back by one cell.
  for (std::size_t p = 0; p < n; ++p) {
    sorted_[cell_start_[cell_[p]]++] = static_cast<std::uint32_t>(p);
  }
  for (std::size_t c = ncell; c > 0; --c) cell_start_[c] = cell_start_[c - 1];
  cell_start_[0] = 0;

  // Visits the candidates of point i in the fixed order; calls f(j) for each neighbour.
  auto visit = [&](std::size_t i, auto&& f) {
    const std::uint32_t ci = cell_[i];
    const std::size_t k0 = ci % dims[0];
    const std::size_t k1 = (ci / dims[0]) % dims[1];
    const std::size_t k2 = ci / (dims[0] * dims[1]);
    const double xi = x[i], yi = y[i], zi = z[i], hi_ = h[i];
    for (std::size_t c2 = k2 > 0 ? k2 - 1 : 0; c2 <= std::min(k2 + 1, dims[2] - 1); ++c2) {
      for (std::size_t c1 = k1 > 0 ? k1 - 1 : 0; c1 <= std::min(k1 + 1, dims[1] - 1); ++c1) {
        const std::size_t row = (c2 * dims[1] + c1) * dims[0];
        const std::size_t a = row + (k0 > 0 ? k0 - 1 : 0);
        const std::size_t b = row + std::min(k0 + 1, dims[0] - 1);
        // Cells a..b are contiguous in the sorted order: one run of points.
        for (std::uint32_t s = cell_start_[a]; s < cell_start_[b + 1]; ++s) {
          const std::uint32_t j = sorted_[s];
          if (j == i) continue;
          const double dx = xi - x[j], dy = yi - y[j], dz = zi - z[j];
          const double reach = hi_ + h[j];  // 2 h_ij
          if (dx * dx + dy * dy + dz * dz < reach * reach) f(j);
        }
      }
    }
  };

  // Pass 1: counts (into offsets_[i + 1]); pass 2: the lists. Points are visited in sorted
  // order so that neighbouring points run on the same thread and share cache lines.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t s = r.begin(); s < r.end(); ++s) {
                        const std::size_t i = sorted_[s];
                        std::size_t count = 0;
                        visit(i, [&](std::uint32_t) { ++count; });
                        offsets_[i + 1] = count;
                      }
                    });
  for (std::size_t i = 0; i < n; ++i) offsets_[i + 1] += offsets_[i];
  if (list_.size() < offsets_[n]) list_.resize(offsets_[n]);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t s = r.begin(); s < r.end(); ++s) {
                        const std::size_t i = sorted_[s];
                        std::uint32_t* out = list_.data() + offsets_[i];
                        visit(i, [&](std::uint32_t j) { *out++ = j; });
                      }
                    });
}

}  // namespace shatter::sph
