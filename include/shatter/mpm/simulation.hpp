#pragma once
// Simulation: owns particles, materials and the sparse grid, and advances them with the MUSL
// stage graph (MPM paper App. A.2).

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "shatter/core/config.hpp"
#include "shatter/core/energy.hpp"
#include "shatter/core/particles.hpp"
#include "shatter/core/solver.hpp"
#include "shatter/material/material_model.hpp"
#include "shatter/parallel/comm.hpp"

namespace shatter {
namespace mpm {
struct State;  // src/mpm/state.hpp
}

class Simulation final : public Solver {
 public:
  // `materials[g]` is the model of every group whose Group::material == g. The store must hold
  // x, v, mass, volume0, rho, energy and, for uGIMP, size0; the engine registers what else its
  // stages and the models need.
  Simulation(SolverConfig config, ParticleStore particles, std::vector<MaterialPtr> materials,
             int threads = 0);
  ~Simulation();

  std::string_view method() const override { return "mpm"; }

  // One MUSL step of size clock().dt. When the step leaves a state whose stable step (Eq. 34) is
  // shorter than the step taken by more than config().retake_ratio (a sudden stiffening, e.g.
  // first contact at hypervelocity), the state before the step is restored and the step taken
  // again with the shorter dt, up to kMaxRetakes times; the caller sees one step of that size.
  void step() override;
  static constexpr int kMaxRetakes = 4;
  // Steps taken again so far (each retake counts once).
  std::uint64_t retakes() const override { return retakes_; }
  // Steps until time() reaches t; the last step is shortened to land on t exactly.
  void advance_to(double t) override;

  const Clock& clock() const override { return clock_; }
  const EnergyBudget& energy() const override { return energy_; }
  const SolverConfig& config() const override { return config_; }
  ParticleStore& particles() override { return particles_; }
  const ParticleStore& particles() const override { return particles_; }
  const std::vector<MaterialPtr>& materials() const { return materials_; }
  int threads() const override { return threads_; }

  // Number of allocated grid blocks (memory grows with these, not with the bounding box).
  std::size_t active_blocks() const;
  std::size_t grid_bytes() const;
  // Total nodal mass of the last step's grid (Eq. 32); equals the particle mass to round-off.
  double grid_mass() const;
  const std::vector<StageTiming>& stage_timings() const override;
  // The step's stages in list order (src/mpm/step.cpp), as this scene builds them: the
  // transfer's filter and remap, the outflow, and the exchanges of a run on several ranks
  // included. What `shatter check SCENE --stages` prints.
  std::vector<std::string> stage_names() const;
  // Distributed runs (docs/mpi.md): this rank's traffic in the halo exchanges and in particle
  // migration since the start, and how often the curve was recut for load balance.
  parallel::Traffic halo_traffic() const;
  parallel::Traffic migrate_traffic() const;
  std::uint64_t rebalances() const;
  // Driven bodies (scene key body.NAME.driven, src/mpm/driven.hpp): the particles of these
  // bodies (IField::body values) keep the velocity they have now, and so do the grid nodes they
  // touch. Call before the first step (and again after a restore). Throws std::invalid_argument
  // when a body has no particle, or on more than one MPI rank (not supported).
  void set_driven(const std::vector<std::int32_t>& bodies);

  // Restores a checkpointed clock and energy accounts (particles come with the store).
  void restore(const Clock& clock, const EnergyBudget& energy) override;
  // Same, with the internal energy at t^{n+1} the next step reports (internal_next()) as it was
  // summed when the checkpoint was written, so the first reported row after a resume is bitwise
  // the uninterrupted run's (a sum over the restored store may differ in the last bit).
  void restore(const Clock& clock, const EnergyBudget& energy, double internal_next) override;
  // Sum m E over the particles at t^{n+1}, reported as EnergyBudget::internal by the next step.
  double internal_next() const override;

 private:
  SolverConfig config_;
  ParticleStore particles_;
  std::vector<MaterialPtr> materials_;
  int threads_ = 0;
  Clock clock_;
  EnergyBudget energy_;
  std::uint64_t retakes_ = 0;
  std::unique_ptr<mpm::State> state_;  // the step's state; references the members above
};

}  // namespace shatter
