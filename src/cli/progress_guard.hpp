#pragma once
// The progress guard of the run loop: a run that can no longer advance stops with a message
// naming the cause, instead of printing "energy error -nan" forever. After every step (and before
// the first) it checks that
//  - every energy account and the time step are finite,
//  - the stable time step (Eq. 34) has not fallen below `dt_floor_ratio` x the first step's
//    (solver.dt_floor_ratio; a collapse by that factor means that many times the steps), and
//  - the step moved the simulated time forward (t + dt == t in floating point is a stall).
// A failure throws NumericalError (particle, field, value, step, time in the message), which the
// run loop turns into the post-mortem snapshot and exit code 3, as for a NaN.
//
// The guard sees only the clock, the energy accounts and the particle columns, so it works with
// any solver that provides those.

#include <limits>

#include "shatter/core/energy.hpp"
#include "shatter/core/particles.hpp"
#include "shatter/mpm/simulation.hpp"

namespace shatter::cli {

class ProgressGuard {
 public:
  // `dt_first`: the stable step of the run's initial state (kept in the checkpoint, so a
  // resumed run uses the same floor). 0 or non-finite leaves the floor check off.
  ProgressGuard(double dt_floor_ratio, double dt_first);

  double dt_first() const { return dt_first_; }
  double dt_floor() const { return floor_; }

  // Checks the state; `time_before` is the time before the step just taken (NaN before the
  // first step, when there is no step to check for a stall).
  void check(const Clock& clock, const EnergyBudget& energy, const ParticleStore& particles,
             double time_before = std::numeric_limits<double>::quiet_NaN()) const;

 private:
  double ratio_;
  double dt_first_;
  double floor_;
};

}  // namespace shatter::cli
