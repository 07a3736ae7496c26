#pragma once
// Particle sets with known answers for the fracture tests: lattice points in simple shapes.

#include <cmath>
#include <cstdint>
#include <functional>
#include <numeric>
#include <random>
#include <vector>

#include <xsimd/xsimd.hpp>

#include "shatter/core/particles.hpp"

namespace shatter::test {

// The native batch (AVX-512 here), the one the constitutive kernels instantiate the policies with.
using Batch = xsimd::batch<double>;

struct Point {
  double x = 0, y = 0, z = 0;
  double vx = 0, vy = 0, vz = 0;
  double mass = 1.0;
  double volume = 1.0;
  double damage = 0.0;
};

inline ParticleStore make_store(const std::vector<Point>& pts) {
  ParticleStore s;
  s.require(FieldSet{Field::x, Field::y, Field::z, Field::vx, Field::vy, Field::vz, Field::mass,
                     Field::volume0, Field::damage});
  s.require(IField::id);
  s.require(IField::fragment);
  s.add_group(0, pts.size());
  for (std::size_t p = 0; p < pts.size(); ++p) {
    s.col(Field::x)[p] = pts[p].x;
    s.col(Field::y)[p] = pts[p].y;
    s.col(Field::z)[p] = pts[p].z;
    s.col(Field::vx)[p] = pts[p].vx;
    s.col(Field::vy)[p] = pts[p].vy;
    s.col(Field::vz)[p] = pts[p].vz;
    s.col(Field::mass)[p] = pts[p].mass;
    s.col(Field::volume0)[p] = pts[p].volume;
    s.col(Field::damage)[p] = pts[p].damage;
    s.col(IField::id)[p] = static_cast<std::int64_t>(p);
  }
  return s;
}

// Lattice points (spacing d, corner at the origin) of an nx x ny x nz block for which keep(i, j,
// k) is true; each point has volume d^3.
inline std::vector<Point> lattice(int nx, int ny, int nz, double d,
                                  const std::function<bool(int, int, int)>& keep) {
  std::vector<Point> pts;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j)
      for (int k = 0; k < nz; ++k)
        if (keep(i, j, k)) {
          Point p;
          p.x = i * d;
          p.y = j * d;
          p.z = k * d;
          p.volume = d * d * d;
          pts.push_back(p);
        }
  return pts;
}

// The store with its particles in a random order (ids travel with the particles).
inline ParticleStore shuffled(const std::vector<Point>& pts, std::uint32_t seed) {
  ParticleStore s = make_store(pts);
  std::vector<std::uint32_t> order(pts.size());
  std::iota(order.begin(), order.end(), 0U);
  std::mt19937 rng(seed);
  std::shuffle(order.begin(), order.end(), rng);
  s.permute(order);
  return s;
}

}  // namespace shatter::test
