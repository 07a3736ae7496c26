#pragma once
// Driven (prescribed-velocity) bodies: every particle of a driven body keeps the velocity it
// started with, and so do the grid nodes it touches (scene key `body.NAME.driven`,
// docs/scenes.md). The grip of a tensile test, a piston, a moving anvil.
//
// How: the prescribed velocity is imposed on the grid nodes the material reaches, as grid
// velocity boundary conditions are imposed in MPM since Sulsky, Zhou & Schreyer 1995 (Comput.
// Phys. Commun. 87, 236-252, doi:10.1016/0010-4655(94)00170-7): after the momentum update (end of
// step 4 of App. A.2, Eq. 27) every node the driven particles reach takes their mass-weighted
// prescribed velocity, v_I = sum_p m_p N_I v*_p / sum_p m_p N_I over driven p, and its
// acceleration is changed by the same amount over dt, so that the FLIP update of a free particle
// near the grip sees it (the free part of the body is dragged through the shared nodes and the
// stress they build). After G2P the driven particles' velocity and displacement are set to the
// prescribed law exactly: interpolation from nodes shared with free material would otherwise
// let them drift by round-off and by the free mass's share.
//
// Energy: the drive does work on the body: force times the driver's velocity, booked per step
// as sum_I J_I . v_I with the impulse J_I = M_I (v_I - v_I,free) the constraint gives node I,
// taken from EnergyBudget::boundary_work (work done *on* the system enters with a minus sign, as
// energy the constraints took enters with a plus), so total + boundary_work stays the reference.
// Where a drive starts against material at rest (a grip glued to a rod at rest, a block pushing
// one), the first steps are an inelastic collision at the interface nodes: the work booked then
// exceeds the energy the body keeps, and the error shows it (-9% at 6 us in
// scenes/verification/tensile-rod.toml, -0.9% at 51.6 us once the pull dominates). Booking the
// nodal kinetic energy change M (v^2 - v_free^2) / 2 instead misses the work the drive does
// against the rod's tension: +51% at 51.6 us in the same scene.
#include <cstdint>
#include <span>
#include <vector>

#include "mpm/stencil.hpp"
#include "shatter/core/particles.hpp"
#include "shatter/grid/sparse_grid.hpp"
#include "shatter/mpm/boundaries.hpp"
#include "shatter/parallel/exact_sum.hpp"

namespace shatter::mpm {

class DrivenBodies {
 public:
  // `bodies`: IField::body values of the driven bodies. Records each driven particle's current
  // velocity (by particle id) as its prescribed velocity. Throws std::invalid_argument naming the
  // body if it has no particle in the store, or if the store has no body column.
  DrivenBodies(const ParticleStore& P, std::span<const std::int32_t> bodies);

  bool empty() const { return ids_.empty(); }
  std::size_t size() const { return ids_.size(); }

  // Prescribed velocity of particle id `id`; null when it is not a driven particle.
  const double* velocity(std::int64_t id) const;

  // After the sort (stencils stored): scatter the driven particles' mass and momentum, m_p N_I
  // and m_p N_I v*_p, to the nodes (serially, in particle order: the sums do not depend on the
  // thread count).
  template <class Shape>
  void scatter(const ParticleStore& P, const SparseGrid& grid, const kernels::StencilCache& cache,
               double inv_h);

  // After the momentum update (velocity in p*, acceleration in f*): nodes with driven mass take
  // the prescribed velocity. Returns the work the drive did on the grid this step (J).
  double constrain(SparseGrid& grid, double dt) const;

  // Sets every driven particle's velocity to its prescribed one (the SPH grips: the scene hands
  // this to SphSolver::set_velocity_constraint).
  void hold(ParticleStore& P) const;

  // After G2P: driven particles take v*_p and displacement v*_p dt. Returns the exact sum of
  // their kinetic energies m |v*|^2 / 2, less those that leave through an outflow face of
  // `outflow` (x + dx past it; null: none), as G2P sums the others'.
  parallel::ExactSum set_particles(ParticleStore& P, double* dx, double* dy, double* dz, double dt,
                                   const Boundaries* outflow) const;

  // A point whose velocity is prescribed: of a driven body, with a recorded velocity.
  bool prescribed(std::int64_t body, std::int64_t id) const {
    return driven(body) && velocity(id) != nullptr;
  }

 private:
  bool driven(std::int64_t body) const;
  std::vector<std::int32_t> bodies_;
  std::vector<std::int64_t> ids_;        // sorted
  std::vector<double> v_;                // 3 per id, same order
  std::vector<std::uint32_t> nodes_;     // nodes with driven mass, in first-touch order
  std::vector<double> node_m_, node_p_;  // per grid node: driven mass; momentum (3 per node)
};

template <class Shape>
void DrivenBodies::scatter(const ParticleStore& P, const SparseGrid& grid,
                           const kernels::StencilCache& cache, double inv_h) {
  constexpr int W = Shape::kWidth;
  const std::size_t nn = grid.nodes().px.size();
  for (const std::uint32_t i : nodes_) {
    if (i < node_m_.size()) {
      node_m_[i] = 0.0;
      node_p_[3 * i] = node_p_[3 * i + 1] = node_p_[3 * i + 2] = 0.0;
    }
  }
  nodes_.clear();
  if (node_m_.size() != nn) {
    node_m_.assign(nn, 0.0);
    node_p_.assign(3 * nn, 0.0);
  }
  const auto body = P.col(IField::body);
  const auto id = P.col(IField::id);
  const auto mass = P.col(Field::mass);
  const double* X[3] = {P.col(Field::x).data(), P.col(Field::y).data(), P.col(Field::z).data()};
  const auto size0 = P.col(Field::size0);
  for (std::size_t p = 0; p < P.size(); ++p) {
    if (!driven(body[p])) continue;
    const double* v = velocity(id[p]);
    if (v == nullptr) continue;
    kernels::Stencil<Shape> st;
    const double x[3] = {X[0][p], X[1][p], X[2][p]};
    st.prepare(cache, p, x, inv_h, 0.5 * size0[p] * inv_h, grid.coord(grid.owner_of(p)));
    const std::uint32_t* nb = grid.particle_neighbours(p);
    for (int a = 0; a < W; ++a) {
      for (int b = 0; b < W; ++b) {
        for (int c = 0; c < W; ++c) {
          const double w = mass[p] * st.w[0][a] * st.w[1][b] * st.w[2][c];
          if (w == 0.0) continue;
          const std::uint32_t i = st.node(nb, a, b, c);
          if (node_m_[i] == 0.0) nodes_.push_back(i);
          node_m_[i] += w;
          for (int d = 0; d < 3; ++d) node_p_[3 * i + d] += w * v[d];
        }
      }
    }
  }
}

}  // namespace shatter::mpm
