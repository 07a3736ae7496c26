// App. A.2 step 5: particle velocities and displacements from the grid (leapfrog), and each
// particle's mechanical energy at t^n for the energy stage.

#include <tbb/enumerable_thread_specific.h>

#include "mpm/loops.hpp"
#include "mpm/stages/stages.hpp"
#include "mpm/state.hpp"
#include "shatter/mpm/kernel_inputs.hpp"

namespace shatter::mpm {
namespace {

// The kernel's inputs: the columns, this step's time steps, the filter's target velocity and
// the FLIP velocity kept for the filter's heat (TransferPolicy).
template <class Shape>
kernels::G2PParticles g2p_setup(State& s) {
  ParticleStore& P = s.particles;
  Scratch& sc = s.scratch;
  kernels::G2PParticles in = g2p_inputs(P, s.inv_h(), sc.dx.data(), sc.dy.data(), sc.dz.data());
  in.stencil = s.stencil_rows<Shape>();
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
  return in;
}

// Whether the g2p stage makes the MUSL remap's scatter (stages/remap.cpp) in its own pass: each
// particle's new momentum m_p v_p^{n+1/2} goes to the nodes right after its update, with the
// stencil its gather used (uGIMP's recomputed row: 91 flops and 9 divisions per point less, and
// one pass less over x, size0, mass and v). Where the remap does more than that scatter it is
// left to its own stage: body copies (contact keeps their step-4 momenta), driven bodies (their
// velocities are set after G2P), the filter passes and the filter heat (they use the momentum
// arrays between the two), APIC (no remap) and several ranks (the halo's per-colour partials).
template <class Shape>
bool fuses_remap(const State& s) {
  if constexpr (!kernels::kRecomputedRows<Shape>) {
    return false;
  } else {
    const TransferPolicy& t = s.transfer;
    return t.remap && !t.affine && !t.filter_stage() && !t.filter_heat && !s.dist() && !s.driven &&
           !s.grid.has_copies();
  }
}

// G2P and the remap's scatter in one pass: blocks colour by colour, as p2g does, each block's
// particles gathered, updated and scattered into a scratch grid, which is then added to the
// remap's node arrays (Scratch::remap; the grid's p* still holds the velocities the other
// blocks gather). The node sums are formed in the order of the remap's own scatter (the same
// colours, blocks, particles and flush), so they are the same bits. The remap stage then only
// takes the arrays over (State::remap_fused). run_body(run, owner, list, window, inputs, scratch).
template <class Shape, class RunBody>
void fused_remap(State& s, RunBody&& run_body) {
  SparseGrid& grid = s.grid;
  SparseGrid::Nodes& N = grid.nodes();
  SparseGrid::Nodes& R = s.scratch.remap;
  for (auto* a : {&R.px, &R.py, &R.pz}) a->assign(N.px.size(), 0.0);
  kernels::P2GParticles remap = p2g_inputs(s.particles, s.inv_h(), false);
  remap.stencil = s.stencil_rows<Shape>();
  for (int c = 0; c < SparseGrid::kColours; ++c) {
    const auto blocks = grid.colour(c);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks.size(), 1),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        kernels::G2PWindow win;
                        kernels::P2GScratch scratch;
                        for (std::size_t k = r.begin(); k < r.end(); ++k) {
                          const std::uint32_t b = blocks[k];
                          kernels::p2g_clear<false, true>(scratch);
                          run_body(grid.owned(b), grid.coord(b), grid.neighbours(b), win, &remap,
                                   &scratch);
                          kernels::p2g_flush<false, true>(scratch, grid.neighbours(b), R);
                        }
                      });
  }
  N.px.swap(R.px);
  N.py.swap(R.py);
  N.pz.swap(R.pz);
  s.remap_fused = true;
}

template <class Shape>
void g2p(State& s) {
  ParticleStore& P = s.particles;
  Scratch& sc = s.scratch;
  const kernels::G2PParticles in = g2p_setup<Shape>(s);
  const double* mass = P.col(Field::mass).data();
  const double half_dt_prev = 0.5 * s.clock.dt_prev;
  const Vec3 g = s.config.gravity;
  double* const potential = sc.potential.empty() ? nullptr : sc.potential.data();
  // The points that leave through an outflow face in this step: x^n + dx past the face, the
  // same sum advance_positions makes (dx + x), so the outflow stage's decision.
  const bool outflow = s.boundaries.has_outflow();
  const auto leaves = [&](std::size_t p) {
    return s.boundaries.outside_outflow(in.dx[p] + in.x[p], in.dy[p] + in.y[p], in.dz[p] + in.z[p]);
  };
  const DrivenBodies* const driven = s.driven.get();
  const auto body = driven != nullptr ? P.col(IField::body) : std::span<const std::int64_t>{};
  const auto id = P.col(IField::id);
  // Velocity at t^n, v^{n-1/2} + a dt^{n-1/2}/2, makes the kinetic energy time-centred with
  // the internal energy (second-order energy error). Summed exactly over the points that stay
  // (the energy stage summed a column of it: 8 B per point): kept per run in a buffer (0 for a
  // point left out, which adds nothing to an exact sum) and summed after the run, which costs
  // less than an exact add inside the kernel; driven points are summed by
  // DrivenBodies::set_particles with their prescribed velocity.
  const double w = in.dt_velocity > 0 ? half_dt_prev / in.dt_velocity : 0.0;
  const auto energies = [&](std::size_t p, const double(&v0)[3]) {
    if (potential != nullptr) {  // else no gravity: zero (Scratch)
      potential[p] = -mass[p] * (g.x() * in.x[p] + g.y() * in.y[p] + g.z() * in.z[p]);
    }
    if (driven != nullptr && driven->prescribed(body[p], id[p])) return 0.0;
    if (outflow && leaves(p)) return 0.0;  // booked by the outflow stage, out of this step's sums
    const double vn[3] = {v0[0] + w * (in.vx[p] - v0[0]), v0[1] + w * (in.vy[p] - v0[1]),
                          v0[2] + w * (in.vz[p] - v0[2])};
    return 0.5 * mass[p] * (vn[0] * vn[0] + vn[1] * vn[1] + vn[2] * vn[2]);
  };
  // 1/2 m_p |v_p|^2 of the velocity each particle scattered in this step's P2G (v^{n-1/2}),
  // summed here, exactly (the same bits in any order and split), where it was kept per particle
  // (8 B) for the energy stage to sum. Outflow removes none of it (its momentum is on the nodes).
  tbb::enumerable_thread_specific<parallel::ExactSum> transferred, kinetic;
  tbb::enumerable_thread_specific<std::vector<double>> run_kinetic;
  // One run of particles: G2P, then their energies; with `remap` (fused_remap), each particle's
  // new momentum scattered into it with the stencil the gather used.
  const auto run_body = [&](std::span<const std::uint32_t> run, const SparseGrid::Coord& owner,
                            const std::uint32_t* nb, kernels::G2PWindow& win,
                            const kernels::P2GParticles* remap, kernels::P2GScratch* scratch) {
    parallel::ExactSum sum;
    std::vector<double>& k = run_kinetic.local();
    k.resize(run.size());
    std::size_t i = 0;  // (the order of the run's points does not matter to an exact sum)
    const auto after = [&](std::size_t p, const double(&v0)[3]) {
      k[i++] = energies(p, v0);
      sum.add(0.5 * mass[p] * (v0[0] * v0[0] + v0[1] * v0[1] + v0[2] * v0[2]));
    };
    if (remap != nullptr) {
      kernels::g2p_block<Shape>(in, run, owner, nb, s.grid.nodes(), win,
                                [&](const auto& st, std::uint32_t p, const double(&v0)[3]) {
                                  after(p, v0);
                                  kernels::p2g_lanes<false>(
                                      st, kernels::p2g_point<false>(*remap, p), *scratch);
                                });
    } else {
      kernels::g2p_block<Shape>(in, run, owner, nb, s.grid.nodes(), win, after);
    }
    transferred.local().add(sum);
    parallel::ExactSum& kin = kinetic.local();
    for (const double e : k) kin.add(e);
  };
  if (fuses_remap<Shape>(s)) {
    fused_remap<Shape>(s, run_body);
  } else {
    for_each_run<kernels::G2PWindow>(
        s.grid, [&](std::span<const std::uint32_t> run, const SparseGrid::Coord& owner,
                    const std::uint32_t* nb,
                    kernels::G2PWindow& win) { run_body(run, owner, nb, win, nullptr, nullptr); });
  }
  s.sums.transferred = parallel::ExactSum{};
  for (const parallel::ExactSum& t : transferred) s.sums.transferred.add(t);
  s.sums.kinetic = parallel::ExactSum{};
  for (const parallel::ExactSum& k : kinetic) s.sums.kinetic.add(k);
  if (s.driven) {
    s.sums.kinetic.add(s.driven->set_particles(P, sc.dx.data(), sc.dy.data(), sc.dz.data(),
                                               s.dt_step, outflow ? &s.boundaries : nullptr));
    // A driven point's velocity is prescribed, not filtered: nothing of it is booked as heat.
    if (in.flip_vx != nullptr) {
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
  return {"g2p",
          {kGeometry | FieldSet{Field::mass}, kGrid | kBlocks | kClock},
          // kGrid: where it makes the remap's scatter (fuses_remap), the momentum arrays
          {kVelocity, kDisplacement | kMechanical | kGrid},
          [&s] { g2p<Shape>(s); }};
}

#define SHATTER_INSTANTIATE(S) template Stage g2p_stage<S>(State & s);
SHATTER_FOR_EACH_SHAPE(SHATTER_INSTANTIATE)

}  // namespace shatter::mpm
