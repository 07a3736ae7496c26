// The MUSL step of the MPM paper, App. A.2: the ordered list of its stages, and the step with
// its retake. Each stage (src/mpm/stages/) declares the data it reads and writes; the stage
// graph orders the stages from those declarations, so stages that share nothing (the energy
// sums and the time-step reduction) run concurrently.

#include <algorithm>
#include <chrono>

#include "mpm/loops.hpp"
#include "mpm/stages/stages.hpp"
#include "mpm/state.hpp"
#include "parallel/mpm/exchanges.hpp"
#include "shatter/core/advance.hpp"
#include "shatter/mpm/simulation.hpp"

namespace shatter::mpm {

// The stages the scene needs, in the order of App. A.2; each exchange (several ranks) is a
// stage of its own: migrate before the sort, halo after each scatter (P2G's, the remap's, and
// each filter pass's: halo_xpic or halo_fmpm, added with the passes by stages/filter.cpp).
template <class Shape>
void add_stages(State& s) {
  StageGraph& g = s.graph;
  if (s.dist()) g.add(parallel::migrate_stage<Shape>(s));        // 0. particles to their owner rank
  g.add(sort_stage<Shape>(s));                                   // 1. sort by block, stencils
  g.add(p2g_stage<Shape>(s));                                    // 1, 3. P2G (Eqs. 29, 32, 33)
  if (s.dist()) g.add(parallel::halo_stage(s));                  // 1b. node sums over ranks
  if (s.config.self_gravity.self) g.add(self_gravity_stage(s));  // 1c. nodal self-gravity
  g.add(grid_update_stage(s));                                   // 2-4. BCs, momentum (Eq. 27)
  if (s.transfer.filter_stage()) add_filter_stages<Shape>(s);    // 5a. XPIC / FMPM passes
  g.add(g2p_stage<Shape>(s));                                    // 5. G2P
  if (s.transfer.filter_heat) g.add(filter_heat_stage(s));       // 5b. filtered loss as heat
  if (s.transfer.remap) {  // 6. MUSL remap: scatter, node sums over ranks, nodal velocity
    const Stage remap = remap_stage<Shape>(s);
    g.add(remap);
    if (s.dist()) g.add(parallel::momentum_halo_stage(s, remap, false));
    g.add(remap_velocity_stage(s));
  }
  g.add(constitutive_stage<Shape>(s));  // 7a, 7b. Eqs. 21, 23; Eqs. 22, 35
  g.add(advance_positions_stage(s));    // x^{n+1}
  if (s.boundaries.has_outflow()) g.add(outflow_stage(s));
  g.add(energy_stage(s));     // energy accounts and the next time step (Eq. 34)
  g.add(time_step_stage(s));  // are independent: they run concurrently
  g.build();
}

void build_stages(State& s) {
  with_shape(s.config.shape, [&]<class Shape>() { add_stages<Shape>(s); });
}

// The graph's stage timings, then the retake's restores, which Simulation::step makes outside the
// graph (Simulation::stage_timings).
void refresh_timings(State& s) {
  const std::vector<StageTiming>& graph = s.graph.timings();
  s.timings.resize(graph.size() + 1);
  std::copy(graph.begin(), graph.end(), s.timings.begin());
  s.timings.back() = s.journal.timing;
}

}  // namespace shatter::mpm

namespace shatter {

void Simulation::step() {
  // Eq. 34 sets dt from the state at t^n; a step in which the signal speed jumps (first contact
  // at hypervelocity: the shocked sound speed plus the viscosity's signal speed) runs at an
  // effective CFL of cfl x dt / (the stable step of the state it leaves) — 1.3 at the first
  // contact of the 15 km/s impact, with a +1.8 % energy error made in that one step. The jump
  // cannot be predicted from particle data at t^n (before contact nothing is compressed), so
  // when the stable step of the state left is shorter than the step taken by more than
  // retake_ratio, the step is taken again with that shorter step. The decision compares two
  // exact maxima (Eq. 34), so it is the same on any thread count. Cost: one copy per step of the
  // columns the step writes, made at the end of the sort stage (docs/stability.md,
  // docs/performance.md); the journal (retake.hpp) undoes the attempt's outflow removals and
  // migration and keeps its re-order, so a retaken step computes the bits it computed before
  // (StepRetake.RetakeRestoresTheStateBitwise).
  mpm::State& s = *state_;
  mpm::Journal& journal = s.journal;
  const auto timed = [&](auto&& f) {
    const auto t0 = std::chrono::steady_clock::now();
    s.arena.execute(f);
    journal.timing.seconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  const bool may_retake = config_.retake_ratio > 0.0;
  if (may_retake) timed([&] { journal.save(s); });
  for (int attempt = 0;; ++attempt) {
    journal.begin_attempt(particles_, may_retake);
    s.dt_step = clock_.dt;
    s.filtering = s.transfer.filters_step(clock_.step);
    s.arena.execute([&] { s.graph.run(); });
    mpm::finish_step(s);
    if (!may_retake || attempt == kMaxRetakes || !(s.dt_step > config_.retake_ratio * clock_.dt)) {
      break;
    }
    const double shorter = clock_.dt;
    timed([&] { journal.restore(s); });
    clock_.dt = shorter;
    ++retakes_;
  }
  journal.end_step(particles_, s.owner_keys);
  mpm::refresh_timings(s);
}

void Simulation::advance_to(double t) {
  advance_clock_to(clock_, t, [this] { step(); });
}

}  // namespace shatter
