// The columns the beta and ejecta-launch sums read (src/fracture/beta.cpp, ejecta_launch.cpp):
// each point's mass, position and velocity, fetched once from the store.
#pragma once

#include <cstddef>
#include <span>

#include <Eigen/Core>

#include "shatter/core/particles.hpp"

namespace shatter::fracture {

struct PointMotion {
  explicit PointMotion(const ParticleStore& store)
      : mass(store.col(Field::mass)),
        x(store.col(Field::x)),
        y(store.col(Field::y)),
        z(store.col(Field::z)),
        vx(store.col(Field::vx)),
        vy(store.col(Field::vy)),
        vz(store.col(Field::vz)) {}

  Eigen::Vector3d position(std::size_t p) const { return {x[p], y[p], z[p]}; }
  Eigen::Vector3d velocity(std::size_t p) const { return {vx[p], vy[p], vz[p]}; }

  std::span<const double> mass, x, y, z, vx, vy, vz;
};

}  // namespace shatter::fracture
