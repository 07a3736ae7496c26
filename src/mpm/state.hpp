#pragma once
// The MPM step's state: what the stages (src/mpm/stages/) read and write besides the particle
// columns. The solver's own data (configuration, store, materials, clock, energy accounts) is
// reached through references, so a stage is a free function of this struct and nothing else.

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <tbb/task_arena.h>

#include "mpm/contact.hpp"
#include "mpm/driven.hpp"
#include "mpm/retake.hpp"
#include "mpm/stage_graph.hpp"
#include "mpm/stencil.hpp"
#include "mpm/transfer.hpp"
#include "parallel/ranks.hpp"
#include "shatter/core/config.hpp"
#include "shatter/core/energy.hpp"
#include "shatter/core/particles.hpp"
#include "shatter/gravity/self_gravity.hpp"
#include "shatter/grid/sparse_grid.hpp"
#include "shatter/material/material_model.hpp"
#include "shatter/mpm/boundaries.hpp"
#include "shatter/parallel/exact_sum.hpp"

namespace shatter::mpm {

// Sums of the step, combined over the ranks after the graph (finish_step).
struct StepSums {
  parallel::ExactSum kinetic, potential, internal, carried, carried_internal, removed;
  // Unresolved kinetic energy (issue 16, docs/outputs.md): sum_p m_p |v_p|^2/2 of the velocities
  // the step's P2G transferred, plus -sum_I |p_I|^2/(2 m_I) of its nodes, in one exact sum.
  parallel::ExactSum transferred, unresolved;
  double fastest = 0.0;  // max_p (c_p + |v_p|) of this rank (Eq. 34)
  std::string failure;   // a numerical failure of this rank in this step (distributed runs)
  std::size_t failure_particle = 0;
};

// Per-particle scratch columns of one step (sized by the sort stage).
struct Scratch {
  // Displacement over the step (G2P -> advance_positions); from advance_positions to the next
  // G2P, the positions at t^n (the buffers exchanged with the position columns), and the sort
  // stage's spare column for the re-order.
  AlignedVector<double> dx, dy, dz;
  // Potential energy at t^n (G2P -> energy). The potential -m g.x is zero for every particle
  // without gravity (the exact sum of zeros is zero): the column is then left empty (8 B per
  // particle less) and the energy stage's sum over it is empty. (The kinetic energy at t^n, and
  // that of the velocity each particle scattered in this step's P2G, v^{n-1/2}, are summed by
  // G2P itself into StepSums::kinetic and ::transferred: no columns.)
  AlignedVector<double> potential;
  // The plain FLIP velocity of the step (G2P -> filter_heat; SolverConfig::filter_heat only).
  AlignedVector<double> flip_vx, flip_vy, flip_vz;
  AlignedVector<double> bx, by, bz;    // body force per unit mass, when the scene has one
  std::vector<double> step4_velocity;  // body-copy node velocities kept through the remap
};

// XPIC (TransferKind::xpic): v^{n+1} kept aside while the grid momentum arrays hold the extra
// passes, the running (S+ S)^{k-1} term, the filtered velocity V*_m + a dt handed to G2P, and
// the interpolated velocities S V of one pass at the particles. FMPM uses the same arrays.
struct FilterArrays {
  std::vector<double> v[3], term[3], target[3];
  AlignedVector<double> w[3];
};

// Test hook (tests/mpi): SHATTER_FAULT_INJECT="nan:RANK:STEP" puts a NaN into one velocity of
// that rank at that step, "throw:RANK:STEP" throws there; never set in a real run.
struct Fault {
  int kind = 0;  // 0 none, 1 nan, 2 throw
  int rank = -1;
  std::uint64_t step = 0;
  static Fault from_environment();  // (stages/time_step.cpp)
};

struct State {
  State(const SolverConfig& cfg, ParticleStore& store, const std::vector<MaterialPtr>& models,
        Clock& clk, EnergyBudget& budget, const TransferPolicy& policy, int threads)
      : config(cfg),
        particles(store),
        materials(models),
        clock(clk),
        energy(budget),
        arena(threads > 0 ? threads : tbb::task_arena::automatic),
        boundaries(cfg.domain, cfg.cell_size),
        transfer(policy) {}

  const SolverConfig& config;
  ParticleStore& particles;
  const std::vector<MaterialPtr>& materials;
  Clock& clock;
  EnergyBudget& energy;

  parallel::Ranks ranks;  // the ranks (docs/mpi.md); with one, no exchange runs
  StepSums sums;
  SparseGrid grid;
  StageGraph graph;
  tbb::task_arena arena;
  // Owner block key per particle (compute_keys: migration and the sort stage, read up to the
  // grid's assign there). Its buffer is lent to the step retake's copy from the end of the sort
  // to the end of the step, when the keys are dead (Journal::save_columns, end_step).
  std::vector<std::uint64_t> owner_keys;
  Scratch scratch;
  // Each particle's stencil (weights, gradients, offsets), stored by the sort stage and read by
  // every transfer of the step (kernels::StencilCache).
  AlignedVector<double> stencil_w;
  std::vector<std::uint8_t> stencil_off;
  Boundaries boundaries;
  // Multi-velocity-field contact: set only when the scene asks for it and has two bodies or
  // more; otherwise the step is the single-field step, bitwise.
  std::unique_ptr<Contact> contact;
  std::unique_ptr<DrivenBodies> driven;           // prescribed-velocity bodies (set_driven)
  std::unique_ptr<gravity::SelfGravity> gravity;  // gravity.self only (stages/gravity.cpp)
  TransferPolicy transfer;                        // decided once, from the configuration
  FilterArrays filter;
  // The step being taken applies the XPIC/FMPM filter (SolverConfig::filter_every); set by
  // Simulation::step from the step counter before the graph runs, the same on a retake.
  bool filtering = true;
  // Some point may leave through an outflow face in this step: G2P made the outflow stage's
  // test (x^n + dx past a face, the same sums) for every point that is not driven, and found
  // one; or the scene has driven bodies, whose displacement is set after G2P. False: the outflow
  // stage has nothing to remove and skips its pass over the points.
  bool outflow_due = true;
  double dt_step = 0.0;        // dt^{n+1/2} of the step being taken
  double internal_next = 0.0;  // sum m E at t^{n+1}, reported with the next step
  double empty_mass = 0.0;     // nodes lighter than this are treated as empty
  Fault fault = Fault::from_environment();
  Journal journal;                   // the step retake's record (retake.hpp)
  std::vector<StageTiming> timings;  // the graph's and the retake's (Simulation::stage_timings)

  bool dist() const { return ranks.dist; }
  double inv_h() const { return 1.0 / config.cell_size; }
  bool uniform_gravity() const {
    const Vec3 g = config.gravity;
    return g.x() != 0.0 || g.y() != 0.0 || g.z() != 0.0;
  }
  kernels::StencilCache stencils(kernels::StencilCache::Mode mode) {
    return {stencil_w.data(), stencil_off.data(), mode};
  }
  // What the transfers read the step's stencils from: the rows the sort stage stored, or for
  // uGIMP (kernels::kRecomputedRows) the positions and sizes they are recomputed from at every
  // read, with the same bits (kernels::StencilCache::kRecompute).
  template <class Shape>
  kernels::StencilCache stencil_rows() {
    if constexpr (!kernels::kRecomputedRows<Shape>) {
      return stencils(kernels::StencilCache::kLoad);
    } else {
      kernels::StencilCache c;
      c.mode = kernels::StencilCache::kRecompute;
      c.x[0] = particles.col(Field::x).data();
      c.x[1] = particles.col(Field::y).data();
      c.x[2] = particles.col(Field::z).data();
      c.size0 = particles.col(Field::size0).data();
      c.inv_h = inv_h();
      c.axisymmetric = config.geometry == Geometry::axisymmetric;
      return c;
    }
  }
};

}  // namespace shatter::mpm
