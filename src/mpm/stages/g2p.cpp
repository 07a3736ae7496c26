// App. A.2 step 5: particle velocities and displacements from the grid (leapfrog), and each
// particle's mechanical energy at t^n for the energy stage.

#include "mpm/loops.hpp"
#include "mpm/stages/stages.hpp"
#include "mpm/state.hpp"
#include "shatter/mpm/kernel_inputs.hpp"

namespace shatter::mpm {
namespace {

// The remap's scatter may run inside G2P's pass (one read of each particle's stencil row, mass
// and velocity while they are in cache) where the scatter is the plain one: a single velocity
// field (no body copies), one rank (the momentum halo exchange follows the remap stage), no
// driven bodies (their velocities are set after G2P) and no filter heat (it reads the FLIP
// velocities between G2P and the remap). Declared at build time; checked again each step.
bool may_fuse_remap(const State& s) {
  return s.transfer.remap && !s.transfer.filter_heat && !s.dist();
}

// G2P and the remap's momentum scatter (App. A.2 steps 5 and 6) block by block, colour by colour
// as the remap's scatter runs (stages/p2g.cpp): each block's particles take their velocity from
// the grid, then scatter m_p v_p into a second set of momentum arrays, since the blocks of a
// later colour still gather the step-4 velocities from the first. Per particle the same
// operations as the two passes, and the node sums are formed in the remap's order: bit for bit.
template <class Shape, class Energies>
void g2p_remap(State& s, const kernels::G2PParticles& in, Energies& energies) {
  SparseGrid& grid = s.grid;
  SparseGrid::Nodes& R = s.remap_nodes;
  for (auto* v : {&R.px, &R.py, &R.pz}) v->assign(grid.nodes().px.size(), 0.0);
  kernels::P2GParticles momentum = p2g_inputs(s.particles, s.inv_h(), false);
  momentum.stencil = s.stencils(kernels::StencilCache::kLoad);
  for (int c = 0; c < SparseGrid::kColours; ++c) {
    const auto blocks = grid.colour(c);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks.size(), 1),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        kernels::G2PWindow win;
                        kernels::P2GScratch scratch;
                        for (std::size_t k = r.begin(); k < r.end(); ++k) {
                          const std::uint32_t b = blocks[k];
                          for_each_list_run(grid, b, [&](auto run, std::uint32_t list) {
                            kernels::g2p_block<Shape>(in, run, grid.coord(b), grid.list(list),
                                                      grid.nodes(), win, energies);
                          });
                          kernels::p2g_block<Shape, false>(momentum, grid.owned(b), grid.coord(b),
                                                           grid.neighbours(b), R, scratch);
                        }
                      });
  }
  SparseGrid::Nodes& N = grid.nodes();
  std::swap(N.px, R.px);
  std::swap(N.py, R.py);
  std::swap(N.pz, R.pz);
}

template <class Shape>
void g2p(State& s) {
  ParticleStore& P = s.particles;
  Scratch& sc = s.scratch;
  kernels::G2PParticles in = g2p_inputs(P, s.inv_h(), sc.dx.data(), sc.dy.data(), sc.dz.data());
  in.stencil = s.stencils(kernels::StencilCache::kLoad);
  in.dt_velocity = 0.5 * (s.clock.dt_prev + s.dt_step);
  in.dt_position = s.dt_step;
  // The share of the filtered grid velocity in the particle update (TransferPolicy).
  in.pic_fraction = s.transfer.filtered_share(s.filtering);
  if (s.transfer.filtered_target(s.filtering)) {
    in.fvx = s.filter.target[0].data();
    in.fvy = s.filter.target[1].data();
    in.fvz = s.filter.target[2].data();
  }
  if (s.transfer.filter_heat) {
    for (auto* c : {&sc.flip_vx, &sc.flip_vy, &sc.flip_vz}) c->resize(P.size());
    in.flip_vx = sc.flip_vx.data();
    in.flip_vy = sc.flip_vy.data();
    in.flip_vz = sc.flip_vz.data();
  }
  const double* mass = P.col(Field::mass).data();
  const double half_dt_prev = 0.5 * s.clock.dt_prev;
  const Vec3 g = s.config.gravity;
  double* const potential = sc.potential.empty() ? nullptr : sc.potential.data();
  // Velocity at t^n, v^{n-1/2} + a dt^{n-1/2}/2, makes the kinetic energy time-centred with
  // the internal energy (second-order energy error).
  const double w = in.dt_velocity > 0 ? half_dt_prev / in.dt_velocity : 0.0;
  const auto energies = [&](std::size_t p, const double(&v0)[3]) {
    const double vn[3] = {v0[0] + w * (in.vx[p] - v0[0]), v0[1] + w * (in.vy[p] - v0[1]),
                          v0[2] + w * (in.vz[p] - v0[2])};
    sc.kinetic[p] = 0.5 * mass[p] * (vn[0] * vn[0] + vn[1] * vn[1] + vn[2] * vn[2]);
    sc.kinetic_transferred[p] = 0.5 * mass[p] * (v0[0] * v0[0] + v0[1] * v0[1] + v0[2] * v0[2]);
    if (potential == nullptr) return;  // no gravity: zero (Scratch)
    potential[p] = -mass[p] * (g.x() * in.x[p] + g.y() * in.y[p] + g.z() * in.z[p]);
  };
  s.remap_fused = may_fuse_remap(s) && !s.driven && !s.grid.has_copies();
  if (s.remap_fused) {
    g2p_remap<Shape>(s, in, energies);
    return;
  }
  for_each_run<kernels::G2PWindow>(
      s.grid, [&](std::span<const std::uint32_t> run, const SparseGrid::Coord& owner,
                  const std::uint32_t* nb, kernels::G2PWindow& win) {
        kernels::g2p_block<Shape>(in, run, owner, nb, s.grid.nodes(), win, energies);
      });
  if (s.driven) {
    s.driven->set_particles(P, sc.dx.data(), sc.dy.data(), sc.dz.data(), sc.kinetic.data(),
                            s.dt_step);
    // A driven point's velocity is prescribed, not filtered: nothing of it is booked as heat.
    if (in.flip_vx != nullptr) {
      const auto id = P.col(IField::id);
      for (std::size_t p = 0; p < P.size(); ++p) {
        if (s.driven->velocity(id[p]) == nullptr) continue;
        in.flip_vx[p] = in.vx[p];
        in.flip_vy[p] = in.vy[p];
        in.flip_vz[p] = in.vz[p];
      }
    }
  }
}

}  // namespace

template <class Shape>
Stage g2p_stage(State& s) {
  const std::uint32_t fused =
      may_fuse_remap(s) ? std::uint32_t{kGrid} : 0U;  // the remap's sums, when fused
  return {"g2p",
          {kGeometry | FieldSet{Field::mass}, kGrid | kBlocks | kClock},
          {kVelocity, kDisplacement | kMechanical | fused},
          [&s] { g2p<Shape>(s); }};
}

#define SHATTER_INSTANTIATE(S) template Stage g2p_stage<S>(State & s);
SHATTER_FOR_EACH_SHAPE(SHATTER_INSTANTIATE)

}  // namespace shatter::mpm
