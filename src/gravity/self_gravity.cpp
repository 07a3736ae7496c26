// Self-gravity for both methods (see shatter/gravity/self_gravity.hpp).

#include "shatter/gravity/self_gravity.hpp"

#include <limits>

namespace shatter::gravity {

SelfGravity::SelfGravity(const GravityConfig& config) : config_(config), mesh_(config.mesh) {}

void SelfGravity::solve(const MassPoints& pts) {
  ax.resize(pts.n);
  ay.resize(pts.n);
  az.resize(pts.n);
  info_ = mesh_.solve(pts, config_.G, {ax.data(), ay.data(), az.data(), nullptr});
}

void SelfGravity::book(EnergyBudget& E, bool first_step) {
  E.gravitational = info_.energy;
  // The solvers fix E.initial before the first step; W at t = 0 joins it once (a retaken first
  // step solves again at the same positions and must not book it twice; a resumed run reads
  // E.initial, W included, from its checkpoint and is past its first step).
  if (first_step && !booked_initial_) E.initial += info_.energy;
  booked_initial_ = true;
}

double SelfGravity::dt_limit(double length) const {
  if (info_.cell <= 0.0) return std::numeric_limits<double>::infinity();
  return gravity_time_step(info_.a_max, length, config_.dt_factor);
}

}  // namespace shatter::gravity
