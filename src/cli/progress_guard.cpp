#include "progress_guard.hpp"

#include <cmath>
#include <string>

#include <fmt/format.h>

namespace shatter::cli {
namespace {

struct Culprit {
  std::size_t particle = 0;
  std::string what;  // "field = value, ..."
};

std::string id_of(const ParticleStore& P, std::size_t p) {
  return P.has(IField::id) ? fmt::format(" (id {})", P.col(IField::id)[p]) : std::string();
}

// The first particle whose own share of a non-finite energy sum is not finite (lowest index, so
// the same particle on any thread count); failing that, the largest finite share (the sum
// overflowed although no single term did).
template <class Share>
Culprit energy_culprit(const ParticleStore& P, const char* label, Share share) {
  Culprit c;
  double largest = -1.0;
  for (std::size_t p = 0; p < P.size(); ++p) {
    const double s = share(p);
    if (!std::isfinite(s)) {
      c.particle = p;
      c.what = fmt::format("{} share m = {} kg, {} = {}", label, P.col(Field::mass)[p], label, s);
      return c;
    }
    if (std::abs(s) > largest) {
      largest = std::abs(s);
      c.particle = p;
    }
  }
  c.what = fmt::format("largest {} share {} J (the sum overflowed)", label, largest);
  return c;
}

// The particle that sets the stable step (Eq. 34: the largest c_p + |v_p|).
Culprit fastest_signal(const ParticleStore& P) {
  Culprit c;
  const bool has_c = P.has(Field::soundspeed);
  double fastest = -1.0;
  for (std::size_t p = 0; p < P.size(); ++p) {
    const double vx = P.col(Field::vx)[p], vy = P.col(Field::vy)[p], vz = P.col(Field::vz)[p];
    const double v = std::sqrt(vx * vx + vy * vy + vz * vz);
    const double s = (has_c ? P.col(Field::soundspeed)[p] : 0.0) + v;
    if (!(s <= fastest)) {  // also takes a NaN, which then stays
      fastest = s;
      c.particle = p;
      if (std::isnan(s)) break;
    }
  }
  if (P.size() == 0) return c;
  const std::size_t p = c.particle;
  const double vx = P.col(Field::vx)[p], vy = P.col(Field::vy)[p], vz = P.col(Field::vz)[p];
  c.what = fmt::format("soundspeed = {:.6g} m/s, |v| = {:.6g} m/s",
                       has_c ? P.col(Field::soundspeed)[p] : 0.0,
                       std::sqrt(vx * vx + vy * vy + vz * vz));
  return c;
}

[[noreturn]] void fail(const ParticleStore& P, const Clock& clock, const std::string& cause,
                       const Culprit& c) {
  throw NumericalError(
      fmt::format("{}; particle {}{}: {}", cause, c.particle, id_of(P, c.particle), c.what),
      c.particle, clock.step);
}

}  // namespace

ProgressGuard::ProgressGuard(double dt_floor_ratio, double dt_first)
    : ratio_(dt_floor_ratio),
      dt_first_(dt_first),
      floor_(std::isfinite(dt_first) && dt_first > 0.0 ? dt_floor_ratio * dt_first : 0.0) {}

void ProgressGuard::check(const Clock& clock, const EnergyBudget& e, const ParticleStore& P,
                          double time_before) const {
  const auto m = P.col(Field::mass);
  // Energies first: an infinite kinetic energy is the root of the dt and stall failures it causes.
  if (!std::isfinite(e.kinetic)) {
    fail(P, clock, fmt::format("non-finite kinetic energy {} J", e.kinetic),
         energy_culprit(P, "kinetic", [&](std::size_t p) {
           const double vx = P.col(Field::vx)[p], vy = P.col(Field::vy)[p],
                        vz = P.col(Field::vz)[p];
           return 0.5 * m[p] * (vx * vx + vy * vy + vz * vz);
         }));
  }
  if (!std::isfinite(e.internal)) {
    fail(P, clock, fmt::format("non-finite internal energy {} J", e.internal),
         energy_culprit(P, "internal",
                        [&](std::size_t p) { return m[p] * P.col(Field::energy)[p]; }));
  }
  const std::pair<const char*, double> accounts[] = {{"potential", e.potential},
                                                     {"boundary work", e.boundary_work},
                                                     {"outflow", e.outflow},
                                                     {"initial", e.initial},
                                                     {"total", e.total()}};
  for (const auto& [name, value] : accounts) {
    if (!std::isfinite(value)) {
      fail(P, clock, fmt::format("non-finite {} energy {} J", name, value), fastest_signal(P));
    }
  }
  if (!std::isfinite(clock.dt) || !(clock.dt > 0.0)) {
    fail(P, clock, fmt::format("time step dt = {} s is not a finite positive number", clock.dt),
         fastest_signal(P));
  }
  if (clock.dt < floor_) {
    fail(P, clock,
         fmt::format("time step collapsed: dt = {:.6e} s is below {:g} x the first step's "
                     "{:.6e} s (solver.dt_floor_ratio)",
                     clock.dt, ratio_, dt_first_),
         fastest_signal(P));
  }
  if (!std::isnan(time_before) && !(clock.time > time_before)) {
    fail(P, clock,
         fmt::format("simulated time stopped advancing: t = {:.17g} s before and after a step of "
                     "dt = {:.6e} s",
                     clock.time, clock.dt_prev),
         fastest_signal(P));
  }
}

}  // namespace shatter::cli
