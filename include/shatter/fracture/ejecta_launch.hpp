#pragma once
// The ejecta's launch record (issue 32): for every point, the first time-series sample at which
// it is ejecta (above the control plane and moving out of the target, include/shatter/fracture/
// beta.hpp, with no speed criterion), its mass, launch speed and launch position. Sorted by
// speed, the cumulative mass M(>v) and the launch distance x from the impact axis are the
// quantities of the point-source ejecta scaling of Housen & Holsapple 2011 (Icarus 211, Eqs. 14
// and 18 as docs/validation-dart.md reads them). The record is kept by particle id, so it does
// not depend on the order of the points, and is read back from its own file on a resume.

#include <cstdint>
#include <map>
#include <string>
#include <string_view>

#include "shatter/core/particles.hpp"
#include "shatter/fracture/beta.hpp"

namespace shatter {

struct EjectaLaunch {
  double time = 0.0;          // s, of the first sample at which the point was ejecta
  double mass = 0.0;          // kg
  double speed = 0.0;         // |v| at launch, m/s
  double normal_speed = 0.0;  // v . n at launch, m/s
  double back_speed = 0.0;    // v . (-d) at launch, against the impact direction, m/s
  double radius = 0.0;        // distance from the impact axis (x_s + s n) at launch, m
  double height = 0.0;        // (x - x_s) . n at launch, m
};

class EjectaLaunches {
 public:
  // The impactor's mass before the impact and its speed (the table's first line; read back by
  // read()).
  void set_impactor(double mass, double speed) {
    impactor_mass_ = mass;
    impact_speed_ = speed;
  }
  double impactor_mass() const { return impactor_mass_; }
  // Adds the points that are ejecta now and were not before (every body's points).
  void record(const ParticleStore& store, const BetaSpec& spec, double time);

  // The table as CSV: a comment line with the impactor's momentum, then one row per launched
  // point, fastest first, with the cumulative mass of the points at least as fast.
  std::string csv() const;
  // Reads a table csv() wrote, keeping the launches at or before `through_time` (a resume from
  // a checkpoint at that time). Throws std::runtime_error naming `source` and the line.
  void read(std::string_view text, const std::string& source, double through_time);

  // 1 + sum m v . (-d) at launch over the launches with |v| >= escape_speed, over m_imp U: beta
  // counted at the crossing of the surface (Raducan et al. 2019's count, docs/validation-dart.md),
  // which keeps the ejecta that have since left the domain. Summed in id order: deterministic.
  double beta_at_launch(double escape_speed) const;

  std::size_t size() const { return launches_.size(); }
  const std::map<std::int64_t, EjectaLaunch>& launches() const { return launches_; }

 private:
  std::map<std::int64_t, EjectaLaunch> launches_;  // by particle id
  double impactor_mass_ = 0.0;                     // kg
  double impact_speed_ = 0.0;                      // m/s
};

}  // namespace shatter
