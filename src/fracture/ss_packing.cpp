// pkdgrav hand-off details: the colour palette (free of ssdefs.h's reserved colours) and the
// packing-safe radius (no two spheres overlap), applied to the records of an ss file.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include <fmt/format.h>

#include "shatter/fracture/fragments.hpp"

namespace shatter {
namespace {

// Tipsy's colour table (which pkdgrav's viewers use) from 3 to 15, less ssdefs.h's planets:
// 5 Sun, 2 Jupiter, 11 Saturn, 6 Uranus, 7 Neptune (N-BodyShop/gasoline ssdefs.h). 0 (black)
// and 1 (white, dust here) are not in it.
constexpr std::array<std::int32_t, 9> kPalette = {3, 4, 8, 9, 10, 12, 13, 14, 15};

// Uniform-grid nearest-neighbour search over the record centres. Cells are hashed by their
// integer coordinates; a point's nearest neighbour is found by searching Chebyshev rings of
// cells around it until the ring's inner distance exceeds the best distance found.
class CentreGrid {
 public:
  explicit CentreGrid(const std::vector<SsRecord>& recs) : recs_(recs) {
    Eigen::Vector3d lo = recs[0].pos, hi = recs[0].pos;
    for (const SsRecord& r : recs) {
      lo = lo.cwiseMin(r.pos);
      hi = hi.cwiseMax(r.pos);
    }
    lo_ = lo;
    // About one point per cell: a cell of the volume per point, with each extent clamped below
    // at ext_max / n^(1/3) so that points on a plane or a line (fragment centres of a mirrored
    // half model lie on the symmetry plane) do not make the cells tiny and the rings many.
    const double n = static_cast<double>(recs.size());
    const double ext_max = std::max((hi - lo).maxCoeff(), 1e-300);
    const Eigen::Vector3d ext = (hi - lo).cwiseMax(ext_max / std::cbrt(n));
    const double c = std::max(std::cbrt(ext.prod() / n), 1e-300);
    cell_ = c;
    rings_ = static_cast<std::int64_t>(std::ceil(ext.maxCoeff() / c)) + 1;
    for (std::size_t i = 0; i < recs.size(); ++i) cells_[key(coords(recs[i].pos))].push_back(i);
  }

  // Distance from record i to the nearest other record (infinity when alone).
  double nearest(std::size_t i) const {
    const auto c = coords(recs_[i].pos);
    double best = std::numeric_limits<double>::infinity();
    for (std::int64_t s = 0; s <= rings_; ++s) {
      // After rings 0 .. s-1, every unseen point lies in ring s or beyond, so at least (s - 1)
      // cells away (a point may sit anywhere in its own cell).
      if (s >= 1 && best <= static_cast<double>(s - 1) * cell_) break;
      visit_ring(c, s, [&](std::size_t j) {
        if (j != i) best = std::min(best, (recs_[j].pos - recs_[i].pos).norm());
      });
    }
    return best;
  }

 private:
  using Coords = std::array<std::int64_t, 3>;
  Coords coords(const Eigen::Vector3d& p) const {
    Coords c{};
    for (int k = 0; k < 3; ++k)
      c[k] = static_cast<std::int64_t>(std::floor((p[k] - lo_[k]) / cell_));
    return c;
  }
  static std::uint64_t key(const Coords& c) {
    // 21 bits per axis (rings_ <= 1025 cells per axis keeps coordinates far below 2^21).
    return (static_cast<std::uint64_t>(c[0]) << 42) | (static_cast<std::uint64_t>(c[1]) << 21) |
           static_cast<std::uint64_t>(c[2]);
  }
  template <class F>
  void visit_ring(const Coords& c, std::int64_t s, F&& f) const {
    for (std::int64_t dx = -s; dx <= s; ++dx) {
      for (std::int64_t dy = -s; dy <= s; ++dy) {
        for (std::int64_t dz = -s; dz <= s; ++dz) {
          if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) != s) continue;
          const Coords n{c[0] + dx, c[1] + dy, c[2] + dz};
          if (n[0] < 0 || n[1] < 0 || n[2] < 0) continue;
          const auto it = cells_.find(key(n));
          if (it == cells_.end()) continue;
          for (std::size_t j : it->second) f(j);
        }
      }
    }
  }

  const std::vector<SsRecord>& recs_;
  Eigen::Vector3d lo_;
  double cell_ = 1.0;
  std::int64_t rings_ = 0;
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> cells_;
};

}  // namespace

std::int32_t ss_body_colour(std::int64_t body) {
  if (body < 0) throw std::invalid_argument(fmt::format("ss_body_colour: body {}", body));
  return kPalette[static_cast<std::size_t>(body) % kPalette.size()];
}

std::int32_t ss_fragment_colour(std::int64_t fragment) {
  return fragment < 0 ? kSsDustColour : ss_body_colour(fragment);
}

const std::vector<std::int32_t>& ss_palette() {
  static const std::vector<std::int32_t> p(kPalette.begin(), kPalette.end());
  return p;
}

SsRadius ss_radius_by_name(const std::string& name) {
  if (name == "equal_volume") return SsRadius::equal_volume;
  if (name == "packing_safe") return SsRadius::packing_safe;
  throw std::invalid_argument(
      fmt::format("unknown ss radius '{}' (equal_volume or packing_safe)", name));
}

std::size_t apply_packing_safe_radius(SsFile& ss) {
  if (ss.records.size() < 2) return 0;
  const CentreGrid grid(ss.records);
  std::vector<double> half(ss.records.size());
  for (std::size_t i = 0; i < half.size(); ++i) half[i] = 0.5 * grid.nearest(i);
  // r_i <= d_i / 2 <= |x_i - x_j| / 2 for every j, so r_i + r_j <= |x_i - x_j|: spheres touch
  // at most (the nearest-neighbour distance d_i is a minimum over all j).
  std::size_t shrunk = 0;
  for (std::size_t i = 0; i < half.size(); ++i) {
    if (half[i] < ss.records[i].radius) {
      ss.records[i].radius = half[i];
      ++shrunk;
    }
  }
  return shrunk;
}

}  // namespace shatter
