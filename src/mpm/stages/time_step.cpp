// The clock advances by the step taken, and this rank's max_p (c_p + |v_p|) is kept for the
// next time step (Eq. 34), which finish_step sets from every rank's; the finite-state check.

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <span>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "mpm/loops.hpp"
#include "mpm/stages/stages.hpp"
#include "mpm/state.hpp"

namespace shatter::mpm {
namespace {

// What check_finite reads.
constexpr Field kChecked[] = {Field::x,   Field::y,   Field::z,   Field::vx,     Field::vy,
                              Field::vz,  Field::sxx, Field::syy, Field::szz,    Field::sxy,
                              Field::syz, Field::sxz, Field::rho, Field::energy, Field::soundspeed};
constexpr FieldSet kCheckedSet =
    kPosition | kVelocity | kStress | FieldSet{Field::rho, Field::energy, Field::soundspeed};

// 1 when the value is not finite (retake.hpp's not_finite_bits, the copy's test).
inline std::uint64_t not_finite(double v) {
  return not_finite_bits(std::bit_cast<std::uint64_t>(v));
}

// Eq. 34's signal speed c_p + |v_p|, the one expression of check_and_fastest and fastest_local.
inline double signal_speed(double c, double vx, double vy, double vz) {
  return c + std::sqrt(vx * vx + vy * vy + vz * vz);
}

// The first particle in [r.begin(), min(r.end(), found)) with a non-finite value in one of the
// columns `fields`, or `found`; the search for the first offender runs only in a chunk that has
// one (rare: the run is about to stop).
std::size_t first_bad_in(const ParticleStore& P, std::span<const Field> fields,
                         const tbb::blocked_range<std::size_t>& r, std::size_t found,
                         std::uint64_t any) {
  for (const Field f : fields) {
    const double* c = P.col(f).data();
    for (std::size_t p = r.begin(); p < r.end(); ++p) any |= not_finite(c[p]);
  }
  if (any == 0) return found;
  for (const Field f : kChecked) {
    const auto c = P.col(f);
    for (std::size_t p = r.begin(); p < std::min(r.end(), found); ++p) {
      if (!std::isfinite(c[p])) {
        found = p;
        break;
      }
    }
  }
  return found;
}

// The checked columns that fastest_local does not read.
constexpr Field kCheckedRest[] = {Field::x,   Field::y,   Field::z,     Field::sxx,
                                  Field::syy, Field::szz, Field::sxy,   Field::syz,
                                  Field::sxz, Field::rho, Field::energy};

// check_finite and fastest_local in one pass over the columns (the time-step stage's: each
// column read once, where the two passes read c and v twice): the first particle with a
// non-finite checked column (n if none) and max_p (c_p + |v_p|) of Eq. 34, the same maximum as
// fastest_local's (max is exact: any split gives the same bits).
struct Checked {
  std::size_t bad;
  double fastest;
};
Checked check_and_fastest(const ParticleStore& P) {
  const std::size_t n = P.size();
  const double* c = P.col(Field::soundspeed).data();
  const double* vx = P.col(Field::vx).data();
  const double* vy = P.col(Field::vy).data();
  const double* vz = P.col(Field::vz).data();
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, n, kParticleGrain), Checked{n, 0.0},
      [&](const tbb::blocked_range<std::size_t>& r, Checked acc) {
        std::uint64_t any = 0;
        double fast = acc.fastest;
        for (std::size_t p = r.begin(); p < r.end(); ++p) {
          any |= not_finite(c[p]) | not_finite(vx[p]) | not_finite(vy[p]) | not_finite(vz[p]);
          fast = std::max(fast, signal_speed(c[p], vx[p], vy[p], vz[p]));
        }
        return Checked{first_bad_in(P, kCheckedRest, r, acc.bad, any), fast};
      },
      [](Checked a, Checked b) {
        return Checked{std::min(a.bad, b.bad), std::max(a.fastest, b.fastest)};
      });
}

// Throws NumericalError for particle `bad` (one of its checked columns is not finite).
[[noreturn]] void throw_not_finite(const State& s, std::size_t bad) {
  const ParticleStore& P = s.particles;
  for (const Field f : kChecked) {
    const double v = P.col(f)[bad];
    if (!std::isfinite(v)) {
      const auto ids = P.col(IField::id);
      throw NumericalError(
          fmt::format("non-finite {} = {} at particle {} (id {}) at step {}, t = {:.6e} s",
                      name_of(f), v, bad, ids[bad], s.clock.step, s.clock.time),
          bad, s.clock.step);
    }
  }
  throw std::logic_error("check_finite: particle flagged with finite columns");
}

void inject_fault(State& s) {
  const Fault& f = s.fault;
  if (f.kind == 0 || f.rank != s.ranks.comm.rank() || f.step != s.clock.step + 1) return;
  if (f.kind == 2) {
    throw std::runtime_error(
        fmt::format("injected fault (SHATTER_FAULT_INJECT) at step {}", f.step));
  }
  if (s.particles.size() > 0) s.particles.col(Field::vx)[0] = std::nan("");
}

void time_step(State& s) {
  inject_fault(s);
  const Checked checked = check_and_fastest(s.particles);
  if (checked.bad != s.particles.size()) {
    if (s.dist()) {
      // A failure is decided for all ranks at once in finish_step, so that no rank waits for
      // one that left.
      try {
        throw_not_finite(s, checked.bad);
      } catch (const NumericalError& e) {
        s.sums.failure = fmt::format("rank {}: {}", s.ranks.comm.rank(), e.what());
        s.sums.failure_particle = e.particle();
      }
    } else {
      throw_not_finite(s, checked.bad);
    }
  }
  Clock& clk = s.clock;
  clk.time += s.dt_step;
  clk.dt_prev = s.dt_step;
  ++clk.step;
  s.sums.fastest = checked.fastest;
}

}  // namespace

Fault Fault::from_environment() {
  Fault f;
  const char* env = std::getenv("SHATTER_FAULT_INJECT");
  if (env == nullptr) return f;
  const std::string v(env);
  const auto a = v.find(':'), b = v.rfind(':');
  if (a == std::string::npos || a == b) return f;
  const std::string kind = v.substr(0, a);
  f.kind = kind == "nan" ? 1 : kind == "throw" ? 2 : 0;
  f.rank = std::atoi(v.substr(a + 1, b - a - 1).c_str());
  f.step = std::strtoull(v.substr(b + 1).c_str(), nullptr, 10);
  return f;
}

void check_finite(const State& s, FieldSet skip) {
  const ParticleStore& P = s.particles;
  const std::size_t n = P.size();
  Field read[std::size(kChecked)];
  std::size_t k = 0;
  for (const Field f : kChecked) {
    if (!skip.has(f)) read[k++] = f;
  }
  const std::span<const Field> fields(read, k);
  // The first offending particle (lowest index), whatever the thread count.
  const std::size_t bad = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, n, kParticleGrain), n,
      [&](const tbb::blocked_range<std::size_t>& r, std::size_t found) {
        return first_bad_in(P, fields, r, found, 0);
      },
      [](std::size_t a, std::size_t b) { return std::min(a, b); });
  if (bad != n) throw_not_finite(s, bad);
}

double fastest_local(const State& s) {
  const ParticleStore& P = s.particles;
  const auto c = P.col(Field::soundspeed);
  const auto vx = P.col(Field::vx), vy = P.col(Field::vy), vz = P.col(Field::vz);
  // max_p (c_p + |v_p|) of Eq. 34; max is exact, so the reduction order does not matter.
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, P.size(), kParticleGrain), 0.0,
      [&](const tbb::blocked_range<std::size_t>& r, double acc) {
        for (std::size_t p = r.begin(); p < r.end(); ++p) {
          acc = std::max(acc, signal_speed(c[p], vx[p], vy[p], vz[p]));
        }
        return acc;
      },
      [](double a, double b) { return std::max(a, b); });
}

double stable_dt(const State& s, double fastest) {
  const SolverConfig& cfg = s.config;
  if (!(fastest > 0.0)) return cfg.dt_max;  // nothing moves and nothing can: any step is stable
  return std::min(cfg.cfl * cfg.cell_size / fastest, cfg.dt_max);  // Eq. 34
}

Stage time_step_stage(State& s) {
  // Under fault injection (tests/mpi) the stage may write a NaN into vx.
  const FieldSet writes = s.fault.kind == 1 ? FieldSet{Field::vx} : FieldSet{};
  return {"time_step", {kCheckedSet, 0}, {writes, kClock}, [&s] { time_step(s); }};
}

}  // namespace shatter::mpm
