#pragma once
// Energy accounting (ISSUE engine item 9). Every Joule that enters or leaves the particles is
// booked, so the total-energy error measures the integrator, not missing terms.

#include <algorithm>
#include <cmath>

namespace shatter {

struct EnergyBudget {
  double kinetic = 0.0;        // sum 1/2 m v^2 (v at the half step the integrator holds)
  double internal = 0.0;       // sum m E: thermal + strain energy
  double potential = 0.0;      // -sum m g.x (uniform gravity)
  double gravitational = 0.0;  // 1/2 sum m phi, self-gravity (shatter/gravity/self_gravity.hpp)
  double boundary_work = 0.0;  // energy constraints took from the particles (APIC only; +)
  double outflow = 0.0;        // energy carried away by particles that left through outflow
  double initial = 0.0;        // total() at t = 0
  double scale = 0.0;          // largest |kinetic| + |internal| seen: the error's denominator
  // Step diagnostics (issue 16), not part of the budget and not checkpointed (recomputed every
  // step): the kinetic energy of the velocities the step's P2G transferred (v^{n-1/2}), and the
  // part of it the grid does not represent, sum_p m_p |v_p|^2/2 - sum_I |p_I|^2/(2 m_I) with the
  // lumped P2G momentum and mass (docs/outputs.md). 0 before the first step and in SPH.
  double transferred_kinetic = 0.0;
  double unresolved_kinetic = 0.0;

  double total() const { return kinetic + internal + potential + gravitational; }
  // Relative total-energy error: (E - E_0 + removed) / scale.
  double error() const {
    const double s = std::max(scale, 1e-300);
    return (total() + boundary_work + outflow - initial) / s;
  }
  // unresolved_kinetic / transferred_kinetic: the step's share in [0, 1]; 0 when nothing moves.
  double unresolved_fraction() const {
    return transferred_kinetic > 0.0 ? unresolved_kinetic / transferred_kinetic : 0.0;
  }
};

}  // namespace shatter
