// The SPH step (include/shatter/sph/solver.hpp lists it), restore and the accessors. The parts
// the step calls are in src/sph/solver_impl.hpp, one file each.

#include "shatter/sph/solver.hpp"
#include "shatter/core/advance.hpp"

#include <stdexcept>

#include "sph/solver_impl.hpp"

namespace shatter::sph {

SphSolver::~SphSolver() = default;

const std::vector<StageTiming>& SphSolver::stage_timings() const {
  return impl_->timings;
}
const NeighbourSearch& SphSolver::neighbours() const {
  return impl_->search;
}
std::size_t SphSolver::bytes() const {
  const Impl& I = *impl_;
  const auto held = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  std::size_t b = I.search.bytes();
  for (const auto* v : {&I.h, &I.h_mid, &I.ax, &I.ay, &I.az, &I.heat, &I.ex, &I.ey, &I.ez, &I.evx,
                        &I.evy, &I.evz, &I.em, &I.erho, &I.ec, &I.alpha, &I.rho_n}) {
    b += held(*v);
  }
  for (const auto* v : {&I.xb, &I.yb, &I.zb, &I.hb, &I.skin}) b += held(*v);
  for (const auto& v : I.a_stress) b += held(v);
  b += held(I.pair_w) + held(I.pair_mask) + held(I.chunk_w) + held(I.chunk_room) +
       held(I.chunk_w_count) + held(I.chunk_mask) + held(I.spill) + held(I.active_count) +
       held(I.order) + held(I.renumber) + held(I.ghosts) + held(I.kept_ghosts) + held(I.leaving);
  for (const auto& v : I.rest) b += held(v);
  for (const auto& v : I.packing) b += held(v);
  for (const auto& v : I.spill) b += held(v);
  return b;
}
std::uint64_t SphSolver::neighbour_builds() const {
  return impl_->builds;
}
std::span<const double> SphSolver::smoothing_length() const {
  return {impl_->h.data(), particles_.size()};
}
std::span<const double> SphSolver::viscosity_alpha() const {
  if (!impl_->switch_on) return {};
  return {impl_->alpha.data(), particles_.size()};
}

void SphSolver::restore(const Clock& clock, const EnergyBudget& energy) {
  if (sph_.viscosity_switch != ViscositySwitch::none) {
    // The switch's alpha is a per-particle state the checkpoint does not hold (the store has no
    // column for it); restarting it at alpha_min would silently change the run.
    throw std::invalid_argument(
        "shatter resume: solver.sph.viscosity_switch = \"morris_monaghan\" cannot be resumed "
        "(the per-particle alpha is not in the checkpoint); rerun from the start");
  }
  clock_ = clock;
  energy_ = energy;
  impl_->lists_valid = false;
  // Steps 5-6 again on the restored columns (no re-order: the checkpointed store is already in
  // the order the original run had after its own re-order at this step).
  impl_->arena.execute([&] { impl_->search_and_forces(false); });
}

void SphSolver::restore(const Clock& clock, const EnergyBudget& energy, double /*internal_next*/) {
  restore(clock, energy);
}

// Steps 1-7 of the header, each a named part.
void SphSolver::step() {
  impl_->arena.execute([&] {
    Impl& I = *impl_;
    const double dt = clock_.dt;
    const double dt_kick = 0.5 * (clock_.dt_prev + dt);
    I.timed(kKick, [&] {
      I.kick(dt_kick);
      I.constrain_velocities(clock_.time + 0.5 * dt);
    });
    I.timed(kRates, [&] {
      I.rates(dt, dt_kick);
      I.heat_from_kick();
    });
    I.timed(kMaterial, [&] {
      I.material(dt);
      I.evolve_switch(dt);
    });
    I.timed(kDrift, [&] {
      I.drift(dt);
      I.reflect_after_drift();
      I.outflow_after_drift();
    });
    clock_.time += dt;
    clock_.dt_prev = dt;
    ++clock_.step;
    I.search_and_forces(true);
    I.timed(kEnergy, [&] {
      I.energy();
      I.next_dt();
    });
  });
}

void SphSolver::advance_to(double t) {
  advance_clock_to(clock_, t, [this] { step(); });
}

}  // namespace shatter::sph
