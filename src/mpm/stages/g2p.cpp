// App. A.2 step 5: particle velocities and displacements from the grid (leapfrog), and each
// particle's mechanical energy at t^n for the energy stage.

#include <atomic>

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
  std::atomic<bool> leaving{false};  // a point that is not driven leaves (State::outflow_due)
  const auto energies = [&](std::size_t p, const double(&v0)[3]) {
    if (potential != nullptr) {  // else no gravity: zero (Scratch)
      potential[p] = -mass[p] * (g.x() * in.x[p] + g.y() * in.y[p] + g.z() * in.z[p]);
    }
    if (driven != nullptr && driven->prescribed(body[p], id[p])) return 0.0;
    if (outflow && leaves(p)) {  // booked by the outflow stage, out of this step's sums
      leaving.store(true, std::memory_order_relaxed);
      return 0.0;
    }
    const double vn[3] = {v0[0] + w * (in.vx[p] - v0[0]), v0[1] + w * (in.vy[p] - v0[1]),
                          v0[2] + w * (in.vz[p] - v0[2])};
    return 0.5 * mass[p] * (vn[0] * vn[0] + vn[1] * vn[1] + vn[2] * vn[2]);
  };
  // 1/2 m_p |v_p|^2 of the velocity each particle scattered in this step's P2G (v^{n-1/2}),
  // summed here, exactly (the same bits in any order and split), where it was kept per particle
  // (8 B) for the energy stage to sum. Outflow removes none of it (its momentum is on the nodes).
  tbb::enumerable_thread_specific<parallel::ExactSum> transferred, kinetic;
  tbb::enumerable_thread_specific<std::vector<double>> run_kinetic;
  for_each_run<kernels::G2PWindow>(
      s.grid, [&](std::span<const std::uint32_t> run, const SparseGrid::Coord& owner,
                  const std::uint32_t* nb, kernels::G2PWindow& win) {
        parallel::ExactSum sum;
        std::vector<double>& k = run_kinetic.local();
        k.resize(run.size());
        std::size_t i = 0;  // (the order of the run's points does not matter to an exact sum)
        kernels::g2p_block<Shape>(
            in, run, owner, nb, s.grid.nodes(), win, [&](std::size_t p, const double(&v0)[3]) {
              k[i++] = energies(p, v0);
              sum.add(0.5 * mass[p] * (v0[0] * v0[0] + v0[1] * v0[1] + v0[2] * v0[2]));
            });
        transferred.local().add(sum);
        parallel::ExactSum& kin = kinetic.local();
        for (const double e : k) kin.add(e);
      });
  s.sums.transferred = parallel::ExactSum{};
  for (const parallel::ExactSum& t : transferred) s.sums.transferred.add(t);
  s.sums.kinetic = parallel::ExactSum{};
  for (const parallel::ExactSum& k : kinetic) s.sums.kinetic.add(k);
  s.outflow_due = leaving.load(std::memory_order_relaxed) || driven != nullptr;
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
          {kVelocity, kDisplacement | kMechanical},
          [&s] { g2p<Shape>(s); }};
}

#define SHATTER_INSTANTIATE(S) template Stage g2p_stage<S>(State & s);
SHATTER_FOR_EACH_SHAPE(SHATTER_INSTANTIATE)

}  // namespace shatter::mpm
