#pragma once
// A 1D problem run by the 3D engine: a column of material points one cell thick along x, between
// slip planes on the y and z faces, so every point moves along x only and all points at one x
// share one state. Ids are the creation indices, and reference positions are kept by id because
// the engine re-orders the particle columns.

#include <cstdint>
#include <functional>
#include <vector>

#include "shatter/core/config.hpp"
#include "shatter/core/particles.hpp"

namespace shatter::verification::detail {

struct Column {
  ParticleStore particles;
  std::vector<double> reference_x;  // X of particle id k
};

// `cells` cells of size h = length / cells along x from x = 0, `per_cell` points per cell along
// x (one across). The points are cell-centred sub-cells of size h / per_cell, which is also
// their uGIMP size.
Column make_column(double length, int cells, int per_cell, double density,
                   const std::function<double(double)>& velocity);

// Slip planes y = 0, y = h, z = 0, z = h; the x faces are set by the caller.
Domain column_domain(double h);

// Mass-weighted root mean square of f(p) over the particles.
double mass_rms(const ParticleStore& particles, const std::function<double(std::size_t)>& f);

}  // namespace shatter::verification::detail
