#pragma once
// Simulation: owns particles, materials and the sparse grid, and advances them with the MUSL
// stage graph (MPM paper App. A.2).

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "shatter/core/particles.hpp"
#include "shatter/engine/config.hpp"
#include "shatter/engine/energy.hpp"
#include "shatter/material/material_model.hpp"

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

class Simulation {
 public:
  // `materials[g]` is the model of every group whose Group::material == g. The store must hold
  // x, v, mass, volume0, rho, energy and, for uGIMP, size0; the engine registers what else its
  // stages and the models need.
  Simulation(SolverConfig config, ParticleStore particles, std::vector<MaterialPtr> materials,
             int threads = 0);
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  // One MUSL step of size clock().dt. When the step leaves a state whose stable step (Eq. 34) is
  // shorter than the step taken by more than config().retake_ratio (a sudden stiffening, e.g.
  // first contact at hypervelocity), the state before the step is restored and the step taken
  // again with the shorter dt, up to kMaxRetakes times; the caller sees one step of that size.
  void step();
  static constexpr int kMaxRetakes = 4;
  // Steps taken again so far (each retake counts once).
  std::uint64_t retakes() const { return retakes_; }
  // Steps until time() reaches t; the last step is shortened to land on t exactly.
  void advance_to(double t);

  const Clock& clock() const { return clock_; }
  double time() const { return clock_.time; }
  const EnergyBudget& energy() const { return energy_; }
  const SolverConfig& config() const { return config_; }
  ParticleStore& particles() { return particles_; }
  const ParticleStore& particles() const { return particles_; }
  const std::vector<MaterialPtr>& materials() const { return materials_; }
  int threads() const { return threads_; }

  // Number of allocated grid blocks (memory grows with these, not with the bounding box).
  std::size_t active_blocks() const;
  std::size_t grid_bytes() const;
  // Total nodal mass of the last step's grid (Eq. 32); equals the particle mass to round-off.
  double grid_mass() const;
  const std::vector<StageTiming>& stage_timings() const;

  // Restores a checkpointed clock and energy accounts (particles come with the store).
  void restore(const Clock& clock, const EnergyBudget& energy);
  // Same, with the internal energy at t^{n+1} the next step reports (internal_next()) as it was
  // summed when the checkpoint was written, so the first reported row after a resume is bitwise
  // the uninterrupted run's (a sum over the restored store may differ in the last bit).
  void restore(const Clock& clock, const EnergyBudget& energy, double internal_next);
  // Sum m E over the particles at t^{n+1}, reported as EnergyBudget::internal by the next step.
  double internal_next() const;

 private:
  struct Impl;
  SolverConfig config_;
  ParticleStore particles_;
  std::vector<MaterialPtr> materials_;
  int threads_ = 0;
  Clock clock_;
  EnergyBudget energy_;
  std::uint64_t retakes_ = 0;
  std::unique_ptr<Impl> impl_;
};

}  // namespace shatter
