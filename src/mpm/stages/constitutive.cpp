// App. A.2 step 7: the strain and spin increments and the density update from the nodal
// velocities (7a, Eqs. 21, 23; APIC's C_p; the hoop rate of the axisymmetric mode), then the
// constitutive update of each material group (7b, Eqs. 22, 35; EOS, strength, damage), one
// composed kernel per group (src/materials), chunk by chunk.
//
// The increments live from 7a to 7b only (issue 35): each chunk of a group's particles takes
// them in a buffer of its task and is updated right after, so the store holds no column of them
// (72 B per point). A chunk starts at the group's first particle plus a multiple of kChunk, a
// multiple of every SIMD width, so the composed kernel's batches and scalar tail fall on the
// same particles as in one update over the whole group: the same bits. Each particle's
// increments depend on its own stencil and the nodes only, so neither the chunks nor the runs
// (consecutive particles with one neighbour list) change a value.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "mpm/loops.hpp"
#include "mpm/stages/stages.hpp"
#include "mpm/state.hpp"
#include "shatter/mpm/kernel_inputs.hpp"

namespace shatter::mpm {
namespace {

// Particles per chunk: a multiple of the SIMD widths (2, 4, 8 doubles) of the composed kernel.
constexpr std::size_t kChunk = 1024;
static_assert(kChunk % 8 == 0);

struct Chunk {
  std::size_t begin, end;
  int material;
};

// The chunks of every group, in store order.
std::vector<Chunk> chunks_of(const ParticleStore& P) {
  std::vector<Chunk> out;
  for (const Group& g : P.groups()) {
    for (std::size_t b = g.range.begin; b < g.range.end; b += kChunk) {
      out.push_back({b, std::min(b + kChunk, g.range.end), g.material});
    }
  }
  return out;
}

// A task's scratch: the chunk's increments (xx, yy, zz, xy, yz, xz; then spin xy, yz, xz), its
// particle indices and the gather's node window.
struct ChunkScratch {
  alignas(64) double inc[9][kChunk];
  std::uint32_t index[kChunk];
  kernels::GradientWindow win;
};

template <class Shape>
void step7(State& s, bool rings) {
  ParticleStore& P = s.particles;
  const std::vector<Chunk> chunks = chunks_of(P);
  kernels::GradientParticles grad = gradient_inputs(P, s.inv_h(), s.dt_step);
  grad.stencil = s.stencil_rows<Shape>();
  if (s.transfer.affine) vgrad_columns(P, grad.vgrad);
  const ConstitutiveContext base{s.dt_step, s.config.cell_size, s.config.viscosity, rings};
  const auto tasks = [&](const tbb::blocked_range<std::size_t>& r) {
    // Not zero-filled: a chunk writes every entry it reads first.
    const auto scratch = std::make_unique_for_overwrite<ChunkScratch>();
    ChunkScratch& w = *scratch;
    for (std::size_t c = r.begin(); c < r.end(); ++c) {
      const Chunk& ch = chunks[c];
      const std::size_t n = ch.end - ch.begin;
      // 7a: the increments into the chunk's buffer, run by run.
      kernels::GradientParticles in = grad;
      double* const e[9] = {w.inc[0], w.inc[1], w.inc[2], w.inc[3], w.inc[4],
                            w.inc[5], w.inc[6], w.inc[7], w.inc[8]};
      in.exx = e[0], in.eyy = e[1], in.ezz = e[2], in.exy = e[3], in.eyz = e[4];
      in.exz = e[5], in.wxy = e[6], in.wyz = e[7], in.wxz = e[8];
      in.inc_begin = ch.begin;
      for (std::size_t k = 0; k < n; ++k) w.index[k] = static_cast<std::uint32_t>(ch.begin + k);
      std::size_t i = 0;
      while (i < n) {
        const std::uint32_t list = s.grid.list_of(ch.begin + i);
        std::size_t j = i + 1;
        while (j < n && s.grid.list_of(ch.begin + j) == list) ++j;
        const std::span<const std::uint32_t> run(w.index + i, j - i);
        const SparseGrid::Coord& owner = s.grid.coord(s.grid.owner_of(ch.begin + i));
        if (rings) {
          kernels::velocity_gradient_block<Shape, true>(in, run, owner, s.grid.list(list),
                                                        s.grid.nodes(), w.win);
        } else {
          kernels::velocity_gradient_block<Shape>(in, run, owner, s.grid.list(list), s.grid.nodes(),
                                                  w.win);
        }
        i = j;
      }
      // 7b: the chunk's constitutive update, reading the buffer.
      IncrementViews views;
      for (int k = 0; k < 6; ++k) views.deps[k] = e[k];
      for (int k = 0; k < 3; ++k) views.dspin[k] = e[6 + k];
      views.begin = ch.begin;
      ConstitutiveContext ctx = base;
      ctx.increments = &views;
      s.materials[static_cast<std::size_t>(ch.material)]->update(P, Range{ch.begin, ch.end}, ctx);
    }
  };
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks.size(), 1), tasks);
}

}  // namespace

template <class Shape>
Stage constitutive_stage(State& s) {
  FieldSet models;
  for (const auto& m : s.materials) models = models | m->fields();
  const FieldSet affine = s.transfer.affine ? kVelocityGradient : FieldSet{};
  // r-z: the hoop rate v_r / r and the damage's R_s read x (kGeometry holds it).
  const bool rings = s.config.geometry == Geometry::axisymmetric;
  return {"constitutive",
          {kGeometry | FieldSet{Field::rho, Field::mass}, kGrid | kBlocks | kClock},
          {kStress | models | affine |
               FieldSet{Field::rho, Field::energy, Field::pressure, Field::soundspeed},
           0},
          [&s, rings] { step7<Shape>(s, rings); }};
}

#define SHATTER_INSTANTIATE(S) template Stage constitutive_stage<S>(State & s);
SHATTER_FOR_EACH_SHAPE(SHATTER_INSTANTIATE)

}  // namespace shatter::mpm
