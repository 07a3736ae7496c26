#pragma once
// Solver: what the run loop (src/cli/run_loop.cpp), checkpoints and resume need from a method.
// Two methods implement it on the same particle store and material library (DESIGN.md
// "Layout"): the MPM Simulation (include/shatter/mpm/simulation.hpp) and the SPH solver
// (include/shatter/sph/solver.hpp). A scene picks one with solver.method; the run loop never
// knows which. One virtual call per step, never per particle.

#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "shatter/core/config.hpp"
#include "shatter/core/energy.hpp"
#include "shatter/core/particles.hpp"

namespace shatter {

// Thrown when the state stops being finite or the time step collapses. The message names the
// particle, the field and the step.
class NumericalError : public std::runtime_error {
 public:
  NumericalError(const std::string& what, std::size_t particle, std::uint64_t step)
      : std::runtime_error(what), particle_(particle), step_(step) {}
  std::size_t particle() const { return particle_; }
  std::uint64_t step() const { return step_; }

 private:
  std::size_t particle_;
  std::uint64_t step_;
};

// The integrator's clock, all that a checkpoint needs besides particles and energy accounts.
struct Clock {
  double time = 0.0;
  double dt = 0.0;       // dt^{n+1/2}: the step about to be taken (Eq. 34)
  double dt_prev = 0.0;  // dt^{n-1/2}; 0 before the first step (leapfrog half kick)
  std::uint64_t step = 0;
};

struct StageTiming {
  std::string name;
  double seconds = 0.0;  // accumulated wall time
};

class Solver {
 public:
  Solver() = default;
  virtual ~Solver() = default;
  Solver(const Solver&) = delete;
  Solver& operator=(const Solver&) = delete;

  // "mpm" or "sph" (the scene's solver.method).
  virtual std::string_view method() const = 0;

  // One step of size clock().dt.
  virtual void step() = 0;
  // Steps until time() reaches t; the last step is shortened to land on t exactly.
  virtual void advance_to(double t) = 0;
  // Steps taken again after a sudden stiffening (0 for a method that never retakes).
  virtual std::uint64_t retakes() const = 0;

  virtual const Clock& clock() const = 0;
  double time() const { return clock().time; }
  virtual const EnergyBudget& energy() const = 0;
  virtual const SolverConfig& config() const = 0;
  virtual ParticleStore& particles() = 0;
  virtual const ParticleStore& particles() const = 0;
  virtual int threads() const = 0;
  virtual const std::vector<StageTiming>& stage_timings() const = 0;

  // Restores a checkpointed clock and energy accounts (particles come with the store); any
  // derived state (neighbour lists, accelerations) is rebuilt from the columns, so a resumed run
  // continues bit for bit.
  virtual void restore(const Clock& clock, const EnergyBudget& energy) = 0;
  // Same, with the internal energy the next reported row starts from, as it was summed when the
  // checkpoint was written (a sum over the restored store may differ in the last bit), so the
  // first row after a resume is bitwise the uninterrupted run's (docs/reliability.md).
  virtual void restore(const Clock& clock, const EnergyBudget& energy, double internal_next) = 0;
  // The internal energy (sum m E) the next step's report starts from; checkpointed with the
  // clock and the energy accounts.
  virtual double internal_next() const = 0;
};

}  // namespace shatter
