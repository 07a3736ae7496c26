#pragma once
// The engine's stage loops over the kernels of kernels/mpm, written as Simulation::Impl runs
// them (src/mpm/simulation.cpp: same grains, same colour-by-colour scatter), so that a stage
// can be timed alone on a prepared SparseGrid.

#include <cstddef>
#include <cstdint>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "bodies.hpp"
#include "mpm/g2p.hpp"
#include "mpm/p2g.hpp"
#include "mpm/velocity_gradient.hpp"
#include "shatter/mpm/kernel_inputs.hpp"  // the engine's own input set-up

namespace shatter::bench {

inline constexpr std::size_t kParticleGrain = 2048;  // as the engine

// The engine's own input set-up (include/shatter/mpm/kernel_inputs.hpp), at the bench's cell size.
inline kernels::P2GParticles p2g_inputs(ParticleStore& P, bool with_force) {
  return mpm::p2g_inputs(P, 1.0 / kCell, with_force);
}

// P2G (kForce) or the MUSL remap's momentum-only scatter (!kForce), as Simulation::Impl::p2g;
// kTable false: the node factors as products in the node loop (kernels::p2g_lanes; same bits).
template <class Shape, bool kForce, bool kTable = true>
void scatter(const kernels::P2GParticles& in, SparseGrid& grid) {
  if constexpr (kForce) {
    grid.clear_nodes();
  } else {
    auto& N = grid.nodes();
    std::fill(N.px.begin(), N.px.end(), 0.0);
    std::fill(N.py.begin(), N.py.end(), 0.0);
    std::fill(N.pz.begin(), N.pz.end(), 0.0);
  }
  for (int c = 0; c < SparseGrid::kColours; ++c) {
    const auto blocks = grid.colour(c);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks.size(), 1),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        kernels::P2GScratch scratch;
                        for (std::size_t k = r.begin(); k < r.end(); ++k) {
                          const std::uint32_t b = blocks[k];
                          kernels::p2g_block<Shape, kForce, false, false, kTable>(
                              in, grid.owned(b), grid.coord(b), grid.neighbours(b), grid.nodes(),
                              scratch);
                        }
                      });
  }
}

// Turns the scattered grid into what G2P and the velocity gradient read (acceleration in f*,
// velocity in p*), without the engine's boundary code: a plain divide by the nodal mass.
inline void nodal_velocities(SparseGrid& grid) {
  auto& N = grid.nodes();
  for (std::size_t i = 0; i < N.mass.size(); ++i) {
    const double inv_m = N.mass[i] > 0.0 ? 1.0 / N.mass[i] : 0.0;
    N.px[i] *= inv_m, N.py[i] *= inv_m, N.pz[i] *= inv_m;
    N.fx[i] *= inv_m, N.fy[i] *= inv_m, N.fz[i] *= inv_m;
  }
}

// The gathers' loop (G2P, velocity gradient), as Simulation::Impl runs it (for_each_run):
// owner blocks in parallel, each block's particles with the block's window scratch.
template <class Window, class Body>
void gather_blocks(const SparseGrid& grid, Body&& body) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, grid.shared_blocks(), 1),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      Window win;
                      for (std::size_t k = r.begin(); k < r.end(); ++k) {
                        const auto b = static_cast<std::uint32_t>(k);
                        if (grid.owned(b).empty()) continue;
                        body(grid.owned(b), grid.coord(b), grid.neighbours(b), win);
                      }
                    });
}

// A prepared body: store sorted by owner block, grid assigned, each particle's stencil stored
// as the engine's sort stage stores it (StencilCache), and scattered, so that every transfer
// reads the stencils back as in the engine.
template <class Shape>
struct Prepared {
  ParticleStore store;
  SparseGrid grid;
  AlignedVector<double> stencil_w;
  std::vector<std::uint8_t> stencil_off;
  explicit Prepared(std::int64_t n) : store(make_body(n)) {
    const auto keys = sort_by_block<Shape>(store);
    grid.assign(keys);
    stencil_w.resize(store.size() * kernels::Stencil<Shape>::kRow);
    stencil_off.resize(store.size());
    const ParticleStore& P = store;
    const double* X[3] = {P.col(Field::x).data(), P.col(Field::y).data(), P.col(Field::z).data()};
    kernels::store_stencils<Shape>(X, P.col(Field::size0).data(), 1.0 / kCell, 0, P.size(),
                                   stencils(kernels::StencilCache::kStore));
    auto in = p2g_inputs(store, true);
    in.stencil = stencils(kernels::StencilCache::kLoad);
    scatter<Shape, true>(in, grid);
    nodal_velocities(grid);
  }
  kernels::StencilCache stencils(kernels::StencilCache::Mode mode) {
    return {stencil_w.data(), stencil_off.data(), mode};
  }
};

}  // namespace shatter::bench
