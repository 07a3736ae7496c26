#pragma once
// SphSolver: Benz & Asphaug's (1995, Sec. 4.1) SPH for solids on the same particle store and
// material library as MPM (DESIGN.md "The SPH step"). One step:
//
//   1. kick      v^{n+1/2} = v^{n-1/2} + a^n (dt^{n-1/2} + dt^{n+1/2}) / 2 (leapfrog,
//                kick-drift-kick in its staggered form; the first step is a half kick)
//   2. rates     gather pass with v^{n+1/2} at the midpoint positions x^n + v^{n+1/2} dt / 2 and
//                h^{n+1/2}: velocity gradient (Eq. 18), its trace the continuity equation
//                (Eq. 16): deps = eps_dot dt, dspin = omega dt, rho^{n+1}; and the kick's viscous
//                heat at the kick's mean velocity, added to the energy
//   3. material  MaterialModel::update per group: the same composed EOS + strength + damage
//                kernel as MPM (Jaumann rotation, energy from deps : sigma), zero bulk viscosity
//   4. drift     x^{n+1} = x^n + v^{n+1/2} dt; a particle that crossed a reflecting face is
//                reflected back, particles beyond an outflow face leave
//   5. search    h^{n+1} from rho^{n+1}; the lists are kept while their Verlet skin covers the
//                motion since they were built, else rebuilt with mirror particles across the
//                symmetry and slip faces (images of the particles within 2 max h of the face);
//                neighbour lists at x^{n+1} (sorted cell lists) for the real particles, over real
//                and mirror particles
//   6. forces    gather pass: a^{n+1} from Eq. 17 (full stress) + Monaghan viscosity (and the
//                per-pair viscous weights the next step's heat uses)
//   7. energy    and the next dt (CFL with the viscous signal speed, and the force criterion)
//
// Smoothing length: h_i = h_factor (m_i / rho_i)^{1/3}. With the continuity density this is the
// integral of dh/dt = h div v / 3 (drho/dt = -rho div v), so h needs no column of its own and a
// checkpoint (which holds rho) restores it exactly. Steps 5-6 are a pure function of the columns,
// so restore() rebuilds them and a resumed run continues bit for bit.

#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "shatter/core/solver.hpp"
#include "shatter/material/material_model.hpp"
#include "shatter/sph/config.hpp"
#include "shatter/sph/neighbours.hpp"

namespace shatter::sph {

class SphSolver final : public Solver {
 public:
  // Same store contract as Simulation: x, v, mass, rho (and energy) present; every group's
  // material in `materials`. SolverConfig supplies cfl, dt_max, dt_min, gravity and
  // reorder_interval; cell_size, shape, transfer and viscosity are MPM settings and unused.
  // Domain faces: none (free surface), symmetry and slip (mirror particles; a particle behind
  // such a face is rejected), outflow (particles beyond it leave, their energy booked as
  // outflow); 'fixed' and body forces are rejected (std::invalid_argument).
  SphSolver(SolverConfig config, SphConfig sph, ParticleStore particles,
            std::vector<MaterialPtr> materials, int threads = 0);
  ~SphSolver() override;

  std::string_view method() const override { return "sph"; }
  void step() override;
  void advance_to(double t) override;
  std::uint64_t retakes() const override { return 0; }

  const Clock& clock() const override { return clock_; }
  const EnergyBudget& energy() const override { return energy_; }
  const SolverConfig& config() const override { return config_; }
  const SphConfig& sph_config() const { return sph_; }
  ParticleStore& particles() override { return particles_; }
  const ParticleStore& particles() const override { return particles_; }
  int threads() const override { return threads_; }
  const std::vector<StageTiming>& stage_timings() const override;
  void restore(const Clock& clock, const EnergyBudget& energy) override;
  // SPH sums every energy of the report at the end of the step that reports it (energy() in
  // solver.cpp), so the checkpointed accounts are all it needs: internal_next is the internal
  // energy already in `energy` and is not used.
  void restore(const Clock& clock, const EnergyBudget& energy, double internal_next) override;
  double internal_next() const override { return energy_.internal; }

  // Prescribed velocities, for tests and studies (the grips of the tensile rod, BA95 Sec. 5.1):
  // called after every kick with t^{n+1/2} and the store, it may overwrite any velocities; the
  // drift and the rates then use them. The kinetic energy it adds or removes is booked as
  // boundary work (at the half-step velocities; the budget is approximate for the driven
  // particles, whose accelerations enter the synchronised kinetic energy). Not in a checkpoint:
  // set it again after a restore. Empty = none.
  using VelocityConstraint = std::function<void(double t, ParticleStore&)>;
  void set_velocity_constraint(VelocityConstraint c) { constraint_ = std::move(c); }

  // The neighbour lists at the current positions, and the smoothing lengths they used.
  const NeighbourSearch& neighbours() const;
  // Bytes the solver holds besides the particle store (capacities): its per-point arrays, the
  // search's lists, cells and buffers, the per-pair viscous weights and its scratch.
  std::size_t bytes() const;
  // Neighbour-list builds so far (with a Verlet skin, fewer than steps).
  std::uint64_t neighbour_builds() const;
  std::span<const double> smoothing_length() const;
  // The Morris & Monaghan switch's alpha per particle (store order); empty without the switch.
  std::span<const double> viscosity_alpha() const;

 private:
  struct Impl;
  SolverConfig config_;
  SphConfig sph_;
  ParticleStore particles_;
  std::vector<MaterialPtr> materials_;
  int threads_ = 0;
  Clock clock_;
  EnergyBudget energy_;
  VelocityConstraint constraint_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace shatter::sph
