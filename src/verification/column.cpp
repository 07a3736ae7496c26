#include "verification/column.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

namespace shatter::verification::detail {

Column make_column(double length, int cells, int per_cell, double density,
                   const std::function<double(double)>& velocity) {
  if (cells < 1 || per_cell < 1) {
    throw std::invalid_argument(
        fmt::format("column: cells ({}) and points per cell ({}) must be >= 1", cells, per_cell));
  }
  const double h = length / cells;
  const double spacing = h / per_cell;
  const std::size_t n = static_cast<std::size_t>(cells) * static_cast<std::size_t>(per_cell);
  Column c;
  ParticleStore& s = c.particles;
  s.require({Field::x, Field::y, Field::z, Field::vx, Field::vy, Field::vz, Field::mass,
             Field::volume0, Field::size0, Field::rho, Field::energy});
  s.require(IField::id);
  const Range r = s.add_group(0, n);
  c.reference_x.resize(n);
  // The point stands for a slab h / per_cell long and h x h across.
  const double volume = spacing * h * h;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t p = r.begin + k;
    const double x = (static_cast<double>(k) + 0.5) * spacing;
    c.reference_x[k] = x;
    s.col(Field::x)[p] = x;
    s.col(Field::y)[p] = 0.5 * h;
    s.col(Field::z)[p] = 0.5 * h;
    s.col(Field::vx)[p] = velocity(x);
    s.col(Field::mass)[p] = density * volume;
    s.col(Field::volume0)[p] = volume;
    // uGIMP's particle domain along x; across, any size keeps the x motion exact because the
    // y and z weights sum to one.
    s.col(Field::size0)[p] = spacing;
    s.col(Field::rho)[p] = density;
    s.col(IField::id)[p] = static_cast<std::int64_t>(k);
  }
  return c;
}

Domain column_domain(double h) {
  Domain d;
  d.lo = Vec3(0.0, 0.0, 0.0);
  d.hi = Vec3(std::numeric_limits<double>::infinity(), h, h);
  d.faces = {BoundaryKind::none, BoundaryKind::none, BoundaryKind::slip,
             BoundaryKind::slip, BoundaryKind::slip, BoundaryKind::slip};
  return d;
}

double mass_rms(const ParticleStore& particles, const std::function<double(std::size_t)>& f) {
  const auto m = particles.col(Field::mass);
  double sum = 0.0, mass = 0.0;
  for (std::size_t p = 0; p < particles.size(); ++p) {
    const double e = f(p);
    sum += m[p] * e * e;
    mass += m[p];
  }
  return std::sqrt(sum / mass);
}

}  // namespace shatter::verification::detail
