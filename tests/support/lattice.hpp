#pragma once
// Test helpers: bodies made of a regular lattice of material points (the paper's 2x2x2 points
// per cell when spacing = h / 2).

#include <cmath>
#include <cstdint>
#include <functional>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "shatter/core/particles.hpp"

namespace shatter::test {

inline void require_basic_fields(ParticleStore& s) {
  s.require({Field::x, Field::y, Field::z, Field::vx, Field::vy, Field::vz, Field::mass,
             Field::volume0, Field::size0, Field::rho, Field::energy});
  s.require(IField::id);
  s.require(IField::body);
}

// Adds a group of points at cell-centred lattice sites inside [lo, hi] that satisfy `inside`,
// with density rho, velocity v(x), and body index `body`. Returns the range.
inline Range add_lattice(ParticleStore& s, int material, const Eigen::Vector3d& lo,
                         const Eigen::Vector3d& hi, double spacing, double rho,
                         const std::function<bool(const Eigen::Vector3d&)>& inside,
                         const std::function<Eigen::Vector3d(const Eigen::Vector3d&)>& velocity,
                         int body = 0) {
  require_basic_fields(s);
  std::vector<Eigen::Vector3d> pts;
  const Eigen::Vector3d n = ((hi - lo) / spacing).array().round();
  for (int i = 0; i < static_cast<int>(n.x()); ++i) {
    for (int j = 0; j < static_cast<int>(n.y()); ++j) {
      for (int k = 0; k < static_cast<int>(n.z()); ++k) {
        const Eigen::Vector3d x = lo + spacing * Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5);
        if (inside(x)) pts.push_back(x);
      }
    }
  }
  const std::size_t first_id = s.size();
  const Range r = s.add_group(material, pts.size());
  const double vol = spacing * spacing * spacing;
  for (std::size_t k = 0; k < pts.size(); ++k) {
    const std::size_t p = r.begin + k;
    s.col(Field::x)[p] = pts[k].x();
    s.col(Field::y)[p] = pts[k].y();
    s.col(Field::z)[p] = pts[k].z();
    const Eigen::Vector3d v = velocity(pts[k]);
    s.col(Field::vx)[p] = v.x();
    s.col(Field::vy)[p] = v.y();
    s.col(Field::vz)[p] = v.z();
    s.col(Field::mass)[p] = rho * vol;
    s.col(Field::volume0)[p] = vol;
    s.col(Field::size0)[p] = spacing;
    s.col(Field::rho)[p] = rho;
    s.col(IField::id)[p] = static_cast<std::int64_t>(first_id + k);
    s.col(IField::body)[p] = body;
  }
  return r;
}

inline Range add_box(ParticleStore& s, int material, const Eigen::Vector3d& lo,
                     const Eigen::Vector3d& hi, double spacing, double rho,
                     const Eigen::Vector3d& v = Eigen::Vector3d::Zero(), int body = 0) {
  return add_lattice(
      s, material, lo, hi, spacing, rho, [](const Eigen::Vector3d&) { return true; },
      [v](const Eigen::Vector3d&) { return v; }, body);
}

inline Range add_sphere(ParticleStore& s, int material, const Eigen::Vector3d& centre,
                        double radius, double spacing, double rho, const Eigen::Vector3d& v,
                        int body = 0) {
  const Eigen::Vector3d r = Eigen::Vector3d::Constant(radius);
  return add_lattice(
      s, material, centre - r, centre + r, spacing, rho,
      [&](const Eigen::Vector3d& x) { return (x - centre).norm() <= radius; },
      [v](const Eigen::Vector3d&) { return v; }, body);
}

// Totals over all particles.
inline Eigen::Vector3d momentum(const ParticleStore& s) {
  Eigen::Vector3d m = Eigen::Vector3d::Zero();
  for (std::size_t p = 0; p < s.size(); ++p) {
    const double mp = s.col(Field::mass)[p];
    m += mp * Eigen::Vector3d(s.col(Field::vx)[p], s.col(Field::vy)[p], s.col(Field::vz)[p]);
  }
  return m;
}

inline double max_abs_stress(const ParticleStore& s) {
  double m = 0.0;
  for (const Field f : {Field::sxx, Field::syy, Field::szz, Field::sxy, Field::syz, Field::sxz}) {
    for (const double v : s.col(f)) m = std::max(m, std::abs(v));
  }
  return m;
}

}  // namespace shatter::test
