#pragma once
// The loops the MPM stages share: the shape dispatch, exact particle sums, the runs of the
// gathers, and the node arrays by index. Grain sizes are fixed (never derived from the thread
// count) so that every reduction splits the same way, and sums come out bitwise identical with
// 1 or N threads.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "mpm/shape.hpp"
#include "shatter/core/config.hpp"
#include "shatter/core/particles.hpp"
#include "shatter/grid/sparse_grid.hpp"
#include "shatter/parallel/exact_sum.hpp"

namespace shatter::mpm {

// Calls f.operator()<Shape>() with the shape-function type the scene chose, so that each stage
// is compiled for one shape and a shape switch is written once.
template <class F>
void with_shape(ShapeKind kind, F&& f) {
  switch (kind) {
    case ShapeKind::linear:
      f.template operator()<kernels::LinearShape>();
      break;
    case ShapeKind::ugimp:
      f.template operator()<kernels::GimpShape>();
      break;
    case ShapeKind::bspline2:
      f.template operator()<kernels::BSpline2Shape>();
      break;
  }
}

// A stage template defined in a .cpp file, compiled for every shape function.
#define SHATTER_FOR_EACH_SHAPE(X) \
  X(kernels::LinearShape)         \
  X(kernels::GimpShape)           \
  X(kernels::BSpline2Shape)

constexpr std::size_t kParticleGrain = 2048;

// What the transfers read of a particle's place: position and undeformed size (uGIMP).
constexpr FieldSet kGeometry = kPosition | FieldSet{Field::size0};

// Every particle column: what a stage that re-orders or removes particles writes.
inline FieldSet all_fields() {
  FieldSet s;
  for (std::size_t i = 0; i < kFieldCount; ++i) s = s.with(static_cast<Field>(i));
  return s;
}

// Energy sums are exact (parallel::ExactSum): the same bits whatever the order of the
// particles in the store, the thread count or the number of ranks that hold them.
template <class F>
parallel::ExactSum exact_sum(std::size_t n, F&& term) {
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, n, kParticleGrain), parallel::ExactSum{},
      [&](const tbb::blocked_range<std::size_t>& r, parallel::ExactSum acc) {
        for (std::size_t p = r.begin(); p < r.end(); ++p) acc.add(term(p));
        return acc;
      },
      [](parallel::ExactSum a, const parallel::ExactSum& b) {
        a.add(b);
        return a;
      });
}

// -|p_I|^2 / (2 m_I) of one block's nodes (v: mass, px, py, pz of the block), the node half of
// the unresolved kinetic energy (stages/grid_update.cpp); empty nodes add nothing.
inline void add_node_unresolved(const double* const (&v)[4], parallel::ExactSum& acc) {
  for (int l = 0; l < SparseGrid::kBlockNodes; ++l) {
    const double M = v[0][l];
    if (!(M > 0.0)) continue;
    acc.add(-0.5 * (v[1][l] * v[1][l] + v[2][l] * v[2][l] + v[3][l] * v[3][l]) / M);
  }
}

// The same over the blocks b < blocks with counted(b), field f of block b at at(b, f).
template <class Counted, class At>
parallel::ExactSum node_unresolved(std::size_t blocks, Counted&& counted, At&& at) {
  return tbb::parallel_reduce(
      tbb::blocked_range<std::uint32_t>(0, static_cast<std::uint32_t>(blocks), 16),
      parallel::ExactSum{},
      [&](const tbb::blocked_range<std::uint32_t>& r, parallel::ExactSum acc) {
        for (std::uint32_t b = r.begin(); b < r.end(); ++b) {
          if (!counted(b)) continue;
          const double* const v[4] = {at(b, 0), at(b, 1), at(b, 2), at(b, 3)};
          add_node_unresolved(v, acc);
        }
        return acc;
      },
      [](parallel::ExactSum a, const parallel::ExactSum& b) {
        a.add(b);
        return a;
      });
}

// The node arrays in the order of parallel::NodeFields: mass, momentum, force.
inline std::array<std::vector<double>*, 7> node_fields(SparseGrid::Nodes& N) {
  return {&N.mass, &N.px, &N.py, &N.pz, &N.fx, &N.fy, &N.fz};
}

// APIC's C_p columns in row-major order, as the transfer kernels index them.
template <class T>
void vgrad_columns(ParticleStore& P, T* (&out)[9]) {
  constexpr Field kOrder[9] = {Field::vgrad_xx, Field::vgrad_xy, Field::vgrad_xz,
                               Field::vgrad_yx, Field::vgrad_yy, Field::vgrad_yz,
                               Field::vgrad_zx, Field::vgrad_zy, Field::vgrad_zz};
  for (int k = 0; k < 9; ++k) out[k] = P.col(kOrder[k]).data();
}

// Block b's particles in consecutive runs that share one neighbour list (one run per block,
// except where bodies meet: then one per body): run(particles, list).
template <class Run>
void for_each_list_run(const SparseGrid& grid, std::uint32_t b, Run&& run) {
  const auto owned = grid.owned(b);
  std::size_t i = 0;
  while (i < owned.size()) {
    const std::uint32_t list = grid.list_of(owned[i]);
    std::size_t j = i + 1;
    while (j < owned.size() && grid.list_of(owned[j]) == list) ++j;
    run(owned.subspan(i, j - i), list);
    i = j;
  }
}

// The particles of every owner block, block by block in parallel, in runs that share one
// neighbour list: the unit of work of the gathers, which copy the run's nodes into a window
// first. Each particle's result depends on its own stencil only, so the split does not change
// any value.
template <class Scratch, class Body>
void for_each_run(const SparseGrid& grid, Body&& body) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, grid.shared_blocks(), 1),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      Scratch scratch;
                      for (std::size_t k = r.begin(); k < r.end(); ++k) {
                        const auto b = static_cast<std::uint32_t>(k);
                        for_each_list_run(grid, b, [&](auto run, std::uint32_t list) {
                          body(run, grid.coord(b), grid.list(list), scratch);
                        });
                      }
                    });
}

template <class F>
void node_loop(std::size_t nodes, F&& body) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nodes, 4096),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i < r.end(); ++i) body(i);
                    });
}

}  // namespace shatter::mpm
