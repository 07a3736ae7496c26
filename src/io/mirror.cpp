#include "shatter/io/mirror.hpp"

#include <algorithm>
#include <stdexcept>

namespace shatter::io {
namespace {

// Number of indices of the component along `axis` (0, 1 or 2); odd = the mirror flips it. Read
// from the column name: "x", "vx", "sxy", "deps_xy", "dspin_xy", "sdev_xy".
int indices_along(Field f, int axis) {
  const char a = static_cast<char>('x' + axis);
  const std::string_view n = name_of(f);
  auto count = [&](std::string_view s) {
    return static_cast<int>(std::count(s.begin(), s.end(), a));
  };
  if (kPosition.has(f)) return count(n);
  if (kVelocity.has(f) || kStress.has(f)) return count(n.substr(1));
  if ((kStrainIncrement | kSpinIncrement | kDeviator).has(f)) {
    return count(n.substr(n.find('_') + 1));
  }
  return 0;  // scalars
}

}  // namespace

ParticleStore mirrored(const ParticleStore& half, int axis) {
  if (axis < 0 || axis > 2) throw std::invalid_argument("mirror axis must be 0, 1 or 2");
  ParticleStore full;
  full.require(half.registered());
  for (std::size_t i = 0; i < kIFieldCount; ++i) {
    if (half.has(static_cast<IField>(i))) full.require(static_cast<IField>(i));
  }
  std::int64_t id_offset = 0;
  if (half.has(IField::id) && half.size() > 0) {
    const auto ids = half.col(IField::id);
    id_offset = *std::max_element(ids.begin(), ids.end()) + 1;
  }
  for (const Group& g : half.groups()) {
    const Range r = full.add_group(g.material, 2 * g.range.size());
    const std::size_t n = g.range.size();
    for (std::size_t i = 0; i < kFieldCount; ++i) {
      const auto f = static_cast<Field>(i);
      if (!half.has(f)) continue;
      const double sign = indices_along(f, axis) % 2 == 1 ? -1.0 : 1.0;
      const auto src = half.col(f);
      auto dst = full.col(f);
      for (std::size_t k = 0; k < n; ++k) {
        dst[r.begin + k] = src[g.range.begin + k];
        dst[r.begin + n + k] = sign * src[g.range.begin + k];
      }
    }
    for (std::size_t i = 0; i < kIFieldCount; ++i) {
      const auto f = static_cast<IField>(i);
      if (!half.has(f)) continue;
      const auto src = half.col(f);
      auto dst = full.col(f);
      const std::int64_t offset = f == IField::id ? id_offset : 0;
      for (std::size_t k = 0; k < n; ++k) {
        dst[r.begin + k] = src[g.range.begin + k];
        dst[r.begin + n + k] = src[g.range.begin + k] + offset;
      }
    }
  }
  return full;
}

}  // namespace shatter::io
