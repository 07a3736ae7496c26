// The run loop's progress guard (src/cli/progress_guard.hpp) and the progress line's ETA, on
// hand-made states: each failure the issue describes stops the run with a NumericalError that
// names the cause, the particle and its values; a healthy state passes.

#include "progress_guard.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "progress.hpp"

namespace shatter::cli {
namespace {

// Three particles at rest but for particle 1, which moves at 3 km/s; sound speed 2 km/s.
ParticleStore store() {
  ParticleStore s;
  s.require(FieldSet{Field::x, Field::y, Field::z, Field::vx, Field::vy, Field::vz, Field::mass,
                     Field::energy, Field::soundspeed});
  s.require(IField::id);
  s.add_group(0, 3);
  for (std::size_t p = 0; p < 3; ++p) {
    s.col(Field::mass)[p] = 1e-3;
    s.col(Field::energy)[p] = 1e3;
    s.col(Field::soundspeed)[p] = 2e3;
    s.col(IField::id)[p] = static_cast<std::int64_t>(100 + p);
  }
  s.col(Field::vx)[1] = 3e3;
  return s;
}

Clock clock_at(double t, double dt) {
  Clock c;
  c.time = t;
  c.dt = dt;
  c.dt_prev = dt;
  c.step = 7;
  return c;
}

EnergyBudget energy_of(const ParticleStore& s) {
  EnergyBudget e;
  for (std::size_t p = 0; p < s.size(); ++p) {
    const double v = s.col(Field::vx)[p];
    e.kinetic += 0.5 * s.col(Field::mass)[p] * v * v;
    e.internal += s.col(Field::mass)[p] * s.col(Field::energy)[p];
  }
  e.initial = e.total();
  return e;
}

// The NumericalError's message and particle, or ("", npos) when the check passed.
std::pair<std::string, std::size_t> failure(const ProgressGuard& g, const Clock& c,
                                            const EnergyBudget& e, const ParticleStore& s,
                                            double before) {
  try {
    g.check(c, e, s, before);
  } catch (const NumericalError& x) {
    EXPECT_EQ(x.step(), c.step);
    return {x.what(), x.particle()};
  }
  return {"", std::string::npos};
}

TEST(ProgressGuard, HealthyStatePasses) {
  const ParticleStore s = store();
  const ProgressGuard g(1e-4, 1e-8);
  EXPECT_EQ(failure(g, clock_at(2e-8, 1e-8), energy_of(s), s, 1e-8).first, "");
  // Before the first step there is no step to check for a stall.
  EXPECT_EQ(
      failure(g, clock_at(0.0, 1e-8), energy_of(s), s, std::numeric_limits<double>::quiet_NaN())
          .first,
      "");
}

TEST(ProgressGuard, InfiniteKineticEnergyNamesTheParticleAndItsShare) {
  // The run: 1/2 m v^2 overflows although v is finite.
  ParticleStore s = store();
  s.col(Field::vx)[2] = 1e200;
  const auto [msg, particle] =
      failure(ProgressGuard(1e-4, 1e-8), clock_at(1e-8, 1e-8), energy_of(s), s, 0.0);
  EXPECT_EQ(particle, 2u);
  EXPECT_NE(msg.find("non-finite kinetic energy inf"), std::string::npos) << msg;
  EXPECT_NE(msg.find("particle 2 (id 102)"), std::string::npos) << msg;
}

TEST(ProgressGuard, NaNInternalEnergyIsNamed) {
  ParticleStore s = store();
  s.col(Field::energy)[0] = std::numeric_limits<double>::quiet_NaN();
  const auto [msg, particle] =
      failure(ProgressGuard(1e-4, 1e-8), clock_at(1e-8, 1e-8), energy_of(s), s, 0.0);
  EXPECT_EQ(particle, 0u);
  EXPECT_NE(msg.find("non-finite internal energy"), std::string::npos) << msg;
}

TEST(ProgressGuard, DtBelowTheFloorNamesTheParticleThatSetsIt) {
  // Floor 1e-4 x 1e-8 s = 1e-12 s; the step is 1e-13 s. Particle 1 has the largest c + |v|.
  const ParticleStore s = store();
  const auto [msg, particle] =
      failure(ProgressGuard(1e-4, 1e-8), clock_at(1e-6, 1e-13), energy_of(s), s, 1e-6 - 1e-13);
  EXPECT_EQ(particle, 1u);
  EXPECT_NE(msg.find("time step collapsed"), std::string::npos) << msg;
  EXPECT_NE(msg.find("solver.dt_floor_ratio"), std::string::npos) << msg;
  EXPECT_NE(msg.find("|v| = 3000"), std::string::npos) << msg;
}

TEST(ProgressGuard, ZeroRatioDisablesTheFloorButNotTheZeroStep) {
  const ParticleStore s = store();
  const ProgressGuard g(0.0, 1e-8);
  EXPECT_EQ(failure(g, clock_at(1e-6, 1e-30), energy_of(s), s, 1e-6 - 1e-13).first, "");
  EXPECT_NE(failure(g, clock_at(1e-6, 0.0), energy_of(s), s, 1e-6 - 1e-13)
                .first.find("not a finite positive number"),
            std::string::npos);
}

TEST(ProgressGuard, TimeThatStopsAdvancingIsAStall) {
  // t + dt == t in floating point: 1e-30 s on 1 s.
  const ParticleStore s = store();
  const auto [msg, particle] =
      failure(ProgressGuard(0.0, 1e-8), clock_at(1.0, 1e-30), energy_of(s), s, 1.0);
  EXPECT_NE(msg.find("simulated time stopped advancing"), std::string::npos) << msg;
}

TEST(ProgressGuard, NonFiniteStepIsRefused) {
  const ParticleStore s = store();
  EXPECT_NE(failure(ProgressGuard(1e-4, 1e-8),
                    clock_at(1e-6, std::numeric_limits<double>::infinity()), energy_of(s), s, 0.0)
                .first.find("not a finite positive number"),
            std::string::npos);
}

TEST(ProgressLine, EtaNeverOverflowsOrGoesNegative) {
  // Was: a collapsed dt made the ETA overflow the integer conversion to a negative number.
  EXPECT_EQ(format_duration(1e300), ">100000h");
  EXPECT_EQ(format_duration(4e8), ">100000h");
  EXPECT_EQ(format_duration(std::numeric_limits<double>::infinity()), "?");
  EXPECT_EQ(format_duration(std::numeric_limits<double>::quiet_NaN()), "?");
  EXPECT_EQ(format_duration(-5.0), "?");
  EXPECT_EQ(format_duration(3.0e8), "83333h20m");
  EXPECT_EQ(format_duration(75.0), "1m15s");
}

}  // namespace
}  // namespace shatter::cli
