#pragma once
// Test helpers of the axisymmetric (r-z) mode: bodies of points in the half-plane y = 0, x = r > 0,
// each standing for its ring (SolverConfig::Geometry::axisymmetric), and the solver settings.

#include <cmath>
#include <cstdint>
#include <functional>
#include <numbers>

#include <Eigen/Core>

#include "shatter/core/config.hpp"
#include "shatter/core/particles.hpp"
#include "support/lattice.hpp"

namespace shatter::test::rz {

using Eigen::Vector3d;

// Cell-centred lattice sites (r, 0, z), r = (i + 1/2) s < r_hi, z = z_lo + (k + 1/2) s < z_hi,
// that satisfy inside(r, z); velocity(r, z) = (v_r, 0, v_z). Each point carries the volume of
// the ring its s x s cell sweeps, 2 pi r s^2 (exact), and that ring's mass.
inline Range add_rz(ParticleStore& s, int material, double r_hi, double z_lo, double z_hi,
                    double spacing, double rho, const std::function<bool(double, double)>& inside,
                    const std::function<Vector3d(double, double)>& velocity, int body = 0) {
  require_basic_fields(s);
  std::vector<std::array<double, 2>> pts;
  const auto nr = static_cast<int>(std::round(r_hi / spacing));
  const auto nz = static_cast<int>(std::round((z_hi - z_lo) / spacing));
  for (int i = 0; i < nr; ++i) {
    for (int k = 0; k < nz; ++k) {
      const double r = (i + 0.5) * spacing, z = z_lo + (k + 0.5) * spacing;
      if (inside(r, z)) pts.push_back({r, z});
    }
  }
  const std::size_t first_id = s.size();
  const Range g = s.add_group(material, pts.size());
  for (std::size_t k = 0; k < pts.size(); ++k) {
    const std::size_t p = g.begin + k;
    const double r = pts[k][0], z = pts[k][1];
    const double vol = 2.0 * std::numbers::pi * r * spacing * spacing;
    const Vector3d v = velocity(r, z);
    s.col(Field::x)[p] = r;
    s.col(Field::y)[p] = 0.0;
    s.col(Field::z)[p] = z;
    s.col(Field::vx)[p] = v.x();
    s.col(Field::vy)[p] = 0.0;
    s.col(Field::vz)[p] = v.z();
    s.col(Field::mass)[p] = rho * vol;
    s.col(Field::volume0)[p] = vol;
    s.col(Field::size0)[p] = spacing;
    s.col(Field::rho)[p] = rho;
    s.col(IField::id)[p] = static_cast<std::int64_t>(first_id + k);
    s.col(IField::body)[p] = body;
  }
  return g;
}

// r-z solver settings: cell h, the axis x = 0 as the symmetry face x_lo, every other face free.
inline SolverConfig config(double h, ShapeKind shape = ShapeKind::bspline2) {
  SolverConfig c;
  c.geometry = Geometry::axisymmetric;
  c.shape = shape;
  c.cell_size = h;
  c.domain.lo.x() = 0.0;
  c.domain.faces[0] = BoundaryKind::symmetry;
  return c;
}

}  // namespace shatter::test::rz
