#include "fracture/rings.hpp"

#include <numbers>

namespace shatter::fracture {

std::vector<double> ring_areas(const ParticleStore& store) {
  const std::size_t n = store.size();
  const auto x = store.col(Field::x), vol0 = store.col(Field::volume0), m = store.col(Field::mass);
  const bool has_rho = store.has(Field::rho);
  const auto rho = has_rho ? store.col(Field::rho) : std::span<const double>{};
  std::vector<double> area(n, 0.0);
  for (std::size_t p = 0; p < n; ++p) {
    if (!(x[p] > 0.0)) continue;
    const double volume = has_rho && rho[p] > 0.0 ? m[p] / rho[p] : vol0[p];
    area[p] = volume / (2.0 * std::numbers::pi * x[p]);
  }
  return area;
}

}  // namespace shatter::fracture
