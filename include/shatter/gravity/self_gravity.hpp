#pragma once
// Self-gravity as the two methods use it: the mesh solve (MeshGravity) over the method's masses
// (MPM: the grid nodes' lumped masses; SPH: the particles), the acceleration of each mass, the
// potential energy booked in the energy budget, and gravity's limit on the time step.

#include <vector>

#include "shatter/core/energy.hpp"
#include "shatter/gravity/config.hpp"
#include "shatter/gravity/mesh_gravity.hpp"

namespace shatter::gravity {

class SelfGravity {
 public:
  explicit SelfGravity(const GravityConfig& config);

  // The field of the masses at themselves: ax, ay, az (size n) until the next solve.
  void solve(const MassPoints& pts);
  // Books W in `E` (EnergyBudget::gravitational); on the first solve of a run (first_step),
  // also in E.initial, which the solvers set before any solve.
  void book(EnergyBudget& E, bool first_step);
  // dt_factor sqrt(length / max |a|): infinite before the first solve.
  double dt_limit(double length) const;
  const SolveInfo& info() const { return info_; }

  std::vector<double> ax, ay, az;

 private:
  GravityConfig config_;
  MeshGravity mesh_;
  SolveInfo info_;
  bool booked_initial_ = false;
};

}  // namespace shatter::gravity
