// App. A.2 steps 1 and 3: mass, momentum and internal force scattered to the grid (Eqs. 29,
// 32, 33), block colour by block colour so that no two tasks write one node.

#include <algorithm>

#include "mpm/loops.hpp"
#include "mpm/stages/stages.hpp"
#include "mpm/state.hpp"
#include "parallel/mpm/exchanges.hpp"
#include "shatter/mpm/kernel_inputs.hpp"

namespace shatter::mpm {
namespace {

bool rz(const State& s) {
  return s.config.geometry == Geometry::axisymmetric;
}

// One run of particles into the nodes of its neighbour list, the kernel chosen by what the
// scatter carries: force (step 1) or momentum only, and APIC's affine momentum.
template <class Shape>
void scatter_run(const kernels::P2GParticles& in, std::span<const std::uint32_t> run,
                 const SparseGrid::Coord& owner, const std::uint32_t* nb, SparseGrid::Nodes& N,
                 kernels::P2GScratch& scratch, bool with_force, bool affine, bool rz) {
  if (with_force && rz) {  // the hoop force (kernels::p2g_point); the scene refuses rz APIC
    kernels::p2g_block<Shape, true, false, true>(in, run, owner, nb, N, scratch);
  } else if (with_force && affine) {
    kernels::p2g_block<Shape, true, true>(in, run, owner, nb, N, scratch);
  } else if (with_force) {
    kernels::p2g_block<Shape, true>(in, run, owner, nb, N, scratch);
  } else {
    kernels::p2g_block<Shape, false>(in, run, owner, nb, N, scratch);
  }
}

// The blocks of colour c in parallel: block(b, scratch).
template <class Block>
void colour_loop(const SparseGrid& grid, int c, Block&& block) {
  const auto blocks = grid.colour(c);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks.size(), 1),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      kernels::P2GScratch scratch;
                      for (std::size_t k = r.begin(); k < r.end(); ++k) block(blocks[k], scratch);
                    });
}

// P2G where bodies meet: the particles of an owner block scatter in runs that share one
// neighbour list (one per body next to a meeting block), into their own body's copies; runs
// that reach copies also scatter their mass gradient (the contact normal). Same colouring as
// p2g, so the sums at every node are still formed in a fixed order.
template <class Shape>
void p2g_bodies(State& s, const kernels::P2GParticles& in, bool with_force) {
  SparseGrid& grid = s.grid;
  const auto first_copy = static_cast<std::uint32_t>(grid.shared_blocks());
  for (int c = 0; c < SparseGrid::kColours; ++c) {
    colour_loop(grid, c, [&](std::uint32_t b, kernels::P2GScratch& scratch) {
      for_each_list_run(grid, b, [&](auto run, std::uint32_t list) {
        const std::uint32_t* nb = grid.list(list);
        scatter_run<Shape>(in, run, grid.coord(b), nb, grid.nodes(), scratch, with_force,
                           s.transfer.affine, rz(s));
        if (with_force && list != b * 8) {
          kernels::mass_gradient_block<Shape>(in, run, grid.coord(b), nb, first_copy, grid.nodes(),
                                              scratch);
        }
      });
    });
  }
}

// The particle side of the scatter: columns, body forces, and the nodes it starts from.
kernels::P2GParticles scatter_inputs(State& s, bool with_force, double* const* velocity) {
  ParticleStore& P = s.particles;
  kernels::P2GParticles in = p2g_inputs(P, s.inv_h(), with_force);
  if (velocity != nullptr) {
    in.vx = velocity[0];
    in.vy = velocity[1];
    in.vz = velocity[2];
  }
  if (s.transfer.affine) vgrad_columns(P, in.vgrad);
  Scratch& sc = s.scratch;
  if (with_force) {
    if (s.config.body_force) {
      for (auto* v : {&sc.bx, &sc.by, &sc.bz}) v->assign(P.size(), 0.0);
      s.config.body_force(s.clock.time, P, sc.bx.data(), sc.by.data(), sc.bz.data());
      in.bx = sc.bx.data();
      in.by = sc.by.data();
      in.bz = sc.bz.data();
    }
    s.grid.clear_nodes();
  } else {
    auto& N = s.grid.nodes();
    std::fill(N.px.begin(), N.px.end(), 0.0);
    std::fill(N.py.begin(), N.py.end(), 0.0);
    std::fill(N.pz.begin(), N.pz.end(), 0.0);
  }
  return in;
}

}  // namespace

template <class Shape>
void p2g(State& s, bool with_force, double* const* velocity) {
  kernels::P2GParticles in = scatter_inputs(s, with_force, velocity);
  in.stencil = s.stencil_rows<Shape>();
  SparseGrid& grid = s.grid;
  if (grid.has_copies()) {
    p2g_bodies<Shape>(s, in, with_force);
    return;
  }
  // Colour by colour: blocks of one colour never share a node (see SparseGrid). On several
  // ranks, the partial sums of each colour at halo blocks are kept apart (halo_capture) and
  // added in colour order once every rank's partials are in (the halo stages).
  const parallel::NodeFields fields =
      with_force ? parallel::kForceExchange : parallel::kMomentumExchange;
  for (int c = 0; c < SparseGrid::kColours; ++c) {
    if (s.dist()) parallel::halo_zero(s, c, fields);
    colour_loop(grid, c, [&](std::uint32_t b, kernels::P2GScratch& scratch) {
      scatter_run<Shape>(in, grid.owned(b), grid.coord(b), grid.neighbours(b), grid.nodes(),
                         scratch, with_force, s.transfer.affine, rz(s));
    });
    if (s.dist()) parallel::halo_capture(s, c, fields);
  }
}

template <class Shape>
Stage p2g_stage(State& s) {
  const FieldSet affine = s.transfer.affine ? kVelocityGradient : FieldSet{};
  return {"p2g",
          {kGeometry | kVelocity | kStress | affine | FieldSet{Field::mass, Field::rho}, kBlocks},
          {{}, kGrid},
          [&s] { p2g<Shape>(s, true); }};
}

#define SHATTER_INSTANTIATE(S)                                               \
  template void p2g<S>(State & s, bool with_force, double* const* velocity); \
  template Stage p2g_stage<S>(State & s);
SHATTER_FOR_EACH_SHAPE(SHATTER_INSTANTIATE)

}  // namespace shatter::mpm
