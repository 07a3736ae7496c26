// After the step's graph: the sums and the next time step over all ranks (exact: integer limb
// sums and a maximum), then the same decisions on every rank.

#include <algorithm>
#include <cmath>
#include <string>

#include "mpm/stages/stages.hpp"
#include "mpm/state.hpp"
#include "parallel/exact_reduce.hpp"
#include "shatter/core/solver_inputs.hpp"

namespace shatter::mpm {
namespace {

// A numerical failure of any rank, or no particle left on any, stops every rank alike.
void check_ranks(State& s, double (&flags)[3]) {
  StepSums& S = s.sums;
  flags[0] = S.fastest;
  flags[1] = S.failure.empty() ? 0.0 : 1.0;
  flags[2] = s.particles.size() > 0 ? 1.0 : 0.0;
  if (s.dist()) s.ranks.comm.max(flags);
  if (flags[1] > 0.0) {
    const std::string what = S.failure.empty()
                                 ? std::string("numerical failure on another rank (reported there)")
                                 : S.failure;
    S.failure.clear();
    throw NumericalError(what, S.failure_particle, s.clock.step);
  }
  if (flags[2] == 0.0) {
    throw NumericalError("every particle has left through the outflow boundaries", 0, s.clock.step);
  }
}

}  // namespace

void finish_step(State& s) {
  double flags[3];
  check_ranks(s, flags);
  StepSums& S = s.sums;
  // The unresolved sum: the transferred kinetic energy plus the (negative) nodal terms, exactly.
  S.unresolved.add(S.transferred);
  constexpr int kSums = 8;
  parallel::ExactSum* sums[kSums] = {&S.kinetic,     &S.potential,        &S.internal,
                                     &S.carried,     &S.carried_internal, &S.removed,
                                     &S.transferred, &S.unresolved};
  if (s.dist()) parallel::sum_over_ranks(s.ranks.comm, sums);
  double v[kSums];
  for (int k = 0; k < kSums; ++k) {
    v[k] = sums[k]->value();
    *sums[k] = parallel::ExactSum{};
  }
  EnergyBudget& E = s.energy;
  E.kinetic = v[0];
  E.potential = v[1];
  E.transferred_kinetic = v[6];
  E.unresolved_kinetic = v[7];
  // Internal energy at t^n was summed at the end of the previous step; what left through an
  // outflow face in this step is booked as outflow instead (stages/positions_outflow.cpp).
  E.internal = s.internal_next - v[4];
  s.internal_next = v[2];
  E.outflow += v[3];
  E.scale = std::max(E.scale, std::abs(E.kinetic) + std::abs(E.internal));
  const double taken = s.transfer.filtered_share(s.filtering);
  if (taken > 0.0) E.boundary_work += taken * v[5];
  S.fastest = flags[0];
  s.clock.dt = stable_dt(s, S.fastest);
  if (s.gravity) s.clock.dt = std::min(s.clock.dt, s.gravity->dt_limit(s.config.cell_size));
  check_new_time_step(s.clock, s.config.dt_min, "no sound speed and no motion, and no dt_max set");
}

}  // namespace shatter::mpm
