#include "shatter/verification/problems.hpp"

#include <chrono>
#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "shatter/material/linear_elastic.hpp"
#include "shatter/mpm/simulation.hpp"
#include "shatter/verification/neo_hookean.hpp"
#include "verification/column.hpp"

namespace shatter::verification {

using std::numbers::pi;

// ---- problem 1: the vibrating bar -----------------------------------------------------------

double VibratingBar::beta() const {
  return (2.0 * mode - 1.0) * pi / (2.0 * length);
}
double VibratingBar::omega() const {
  return beta() * std::sqrt(young / density);
}
double VibratingBar::period() const {
  return 2.0 * pi / omega();
}
double VibratingBar::velocity(double x, double t) const {
  return v0 * std::cos(omega() * t) * std::sin(beta() * x);
}
double VibratingBar::displacement(double x, double t) const {
  return v0 / omega() * std::sin(omega() * t) * std::sin(beta() * x);
}
double VibratingBar::centre_of_mass_velocity(double t) const {
  // (1/L) int_0^L v dx; 1 - cos(beta L) = 1 for every mode since beta L = (2n - 1) pi / 2.
  return v0 * (1.0 - std::cos(beta() * length)) / (beta() * length) * std::cos(omega() * t);
}

namespace {

SolverConfig column_config(const RunSettings& run, double h) {
  SolverConfig cfg;
  cfg.shape = run.shape;
  cfg.transfer = run.transfer;
  cfg.pic_fraction = run.pic_fraction;
  cfg.xpic_order = run.xpic_order;
  cfg.fmpm_order = run.fmpm_order;
  cfg.filter_every = run.filter_every;
  cfg.cell_size = h;
  cfg.cfl = run.cfl;
  cfg.domain = detail::column_domain(h);
  return cfg;
}

// The particle column of a 1-D problem, at its velocity at t = 0.
template <class Problem>
detail::Column initial_column(const Problem& problem, const RunSettings& run) {
  return detail::make_column(problem.length, run.cells, problem.points_per_cell, problem.density,
                             [&](double x) { return problem.velocity(x, 0.0); });
}

// The cost of a run of cell size h started (set-up included) at t0 and now done.
RunCost cost_of(const Simulation& sim, double h, std::chrono::steady_clock::time_point t0) {
  RunCost c;
  c.cell_size = h;
  c.steps = sim.clock().step;
  c.particles = sim.particles().size();
  c.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return c;
}

// Steps the simulation to t_end, one stable step at a time, calling sample(t_x, t_v) after each
// step with the time of the positions (t^{n+1}) and of the stored velocities: the leapfrog keeps
// v^{n+1/2}, which belongs to the middle of the step just taken (Fig. 16).
template <class Sample>
void run_to(Simulation& sim, double t_end, Sample&& sample) {
  while (sim.time() < t_end) {
    const double t_before = sim.time();
    const std::uint64_t n = sim.clock().step;
    sim.advance_to(std::min(t_end, t_before + sim.clock().dt));
    if (sim.clock().step == n) continue;  // a sliver merged into the previous step
    const double dt = sim.clock().dt_prev;
    sample(t_before + dt, t_before + 0.5 * dt);
  }
}

}  // namespace

BarErrors run_vibrating_bar(const VibratingBar& problem, const RunSettings& run) {
  const auto t0 = std::chrono::steady_clock::now();
  const double h = problem.length / run.cells;
  detail::Column column = initial_column(problem, run);
  const std::vector<double> X = std::move(column.reference_x);

  SolverConfig cfg = column_config(run, h);
  cfg.domain.faces[0] = problem.wall;  // x = 0 clamped; x = L stays free (open grid)
  // Poisson 0: no lateral stress, so the slip planes leave the 1D bar solution exact.
  std::vector<MaterialPtr> materials{
      std::make_shared<LinearElastic>(problem.density, problem.young, 0.0)};
  Simulation sim(cfg, std::move(column.particles), materials, run.threads);

  const double amplitude = problem.centre_of_mass_velocity(0.0);
  double max_err = 0.0, sum_sq = 0.0, energy_max = 0.0;
  std::uint64_t samples = 0;
  double t_x = 0.0, t_v = 0.0;
  run_to(sim, problem.periods * problem.period(), [&](double tx, double tv) {
    energy_max = std::max(energy_max, std::abs(sim.energy().error()));
    const ParticleStore& P = sim.particles();
    const auto m = P.col(Field::mass), vx = P.col(Field::vx);
    double mv = 0.0, mass = 0.0;
    for (std::size_t p = 0; p < P.size(); ++p) {
      mv += m[p] * vx[p];
      mass += m[p];
    }
    const double err = std::abs(mv / mass - problem.centre_of_mass_velocity(tv)) / amplitude;
    max_err = std::max(max_err, err);
    sum_sq += err * err;
    ++samples;
    t_x = tx;
    t_v = tv;
  });

  const ParticleStore& P = sim.particles();
  const auto ids = P.col(IField::id);
  const auto x = P.col(Field::x), vx = P.col(Field::vx);
  BarErrors out;
  out.com_velocity_max = max_err;
  out.energy_error_max = energy_max;
  out.com_velocity_rms =
      std::sqrt(sum_sq / static_cast<double>(std::max<std::uint64_t>(samples, 1)));
  out.displacement_l2 = detail::mass_rms(P,
                                         [&](std::size_t p) {
                                           const double Xp = X[static_cast<std::size_t>(ids[p])];
                                           return x[p] - Xp - problem.displacement(Xp, t_x);
                                         }) /
                        (problem.v0 / problem.omega());
  out.velocity_l2 = detail::mass_rms(P,
                                     [&](std::size_t p) {
                                       const double Xp = X[static_cast<std::size_t>(ids[p])];
                                       return vx[p] - problem.velocity(Xp, t_v);
                                     }) /
                    problem.v0;
  static_cast<RunCost&>(out) = cost_of(sim, h, t0);
  return out;
}

// ---- problem 2: manufactured solution ---------------------------------------------------------

double ManufacturedSolution::wave_speed() const {
  return std::sqrt(young / density);
}
double ManufacturedSolution::displacement(double X, double t) const {
  const double k = pi / length;
  return amplitude * std::sin(k * X) * std::sin(wave_speed() * k * t);
}
double ManufacturedSolution::velocity(double X, double t) const {
  const double k = pi / length, w = wave_speed() * k;
  return amplitude * w * std::sin(k * X) * std::cos(w * t);
}
double ManufacturedSolution::acceleration(double X, double t) const {
  const double k = pi / length, w = wave_speed() * k;
  return -amplitude * w * w * std::sin(k * X) * std::sin(w * t);
}
double ManufacturedSolution::deformation_gradient(double X, double t) const {
  const double k = pi / length;
  return 1.0 + amplitude * k * std::cos(k * X) * std::sin(wave_speed() * k * t);
}
double ManufacturedSolution::body_force(double X, double t) const {
  const UniaxialNeoHookean law(density, young, poisson);
  const double k = pi / length;
  const double dF_dX = -amplitude * k * k * std::sin(k * X) * std::sin(wave_speed() * k * t);
  // dP/dX = (dP/dF) (dF/dX); P = sigma_xx for uniaxial strain (see neo_hookean.hpp).
  return acceleration(X, t) - law.tangent(deformation_gradient(X, t)) * dF_dX / density;
}

MmsErrors run_manufactured_solution(const ManufacturedSolution& problem, const RunSettings& run) {
  const auto t0 = std::chrono::steady_clock::now();
  const double h = problem.length / run.cells;
  detail::Column column = initial_column(problem, run);
  // Shared with the body-force hook, which lives in the solver config.
  const auto X = std::make_shared<const std::vector<double>>(std::move(column.reference_x));

  SolverConfig cfg = column_config(run, h);
  cfg.domain.hi.x() = problem.length;
  cfg.domain.faces[0] = problem.wall;  // u(0, t) = 0
  cfg.domain.faces[1] = problem.wall;  // u(L, t) = 0
  cfg.body_force = [X, problem](double t, const ParticleStore& P, double* bx, double*, double*) {
    const auto ids = P.col(IField::id);
    for (std::size_t p = 0; p < P.size(); ++p) {
      bx[p] = problem.body_force((*X)[static_cast<std::size_t>(ids[p])], t);
    }
  };
  std::vector<MaterialPtr> materials{
      std::make_shared<UniaxialNeoHookean>(problem.density, problem.young, problem.poisson)};
  Simulation sim(cfg, std::move(column.particles), materials, run.threads);

  auto l2 = [&](double t) {
    const ParticleStore& P = sim.particles();
    const auto ids = P.col(IField::id);
    const auto x = P.col(Field::x);
    return detail::mass_rms(P, [&](std::size_t p) {
      const double Xp = (*X)[static_cast<std::size_t>(ids[p])];
      return x[p] - Xp - problem.displacement(Xp, t);
    });
  };
  MmsErrors out;
  double t_x = 0.0;
  double unresolved_dt = 0.0, transferred_dt = 0.0;
  run_to(sim, problem.t_end, [&](double tx, double) {
    out.displacement_l2_max = std::max(out.displacement_l2_max, l2(tx));
    unresolved_dt += sim.energy().unresolved_kinetic * sim.clock().dt_prev;
    transferred_dt += sim.energy().transferred_kinetic * sim.clock().dt_prev;
    t_x = tx;
  });
  out.unresolved_fraction_run = transferred_dt > 0.0 ? unresolved_dt / transferred_dt : 0.0;
  out.displacement_l2 = l2(t_x);
  out.unresolved_fraction = sim.energy().unresolved_fraction();
  static_cast<RunCost&>(out) = cost_of(sim, h, t0);
  return out;
}

// ---- convergence order ------------------------------------------------------------------------

double fitted_order(std::span<const double> h, std::span<const double> error) {
  if (h.size() != error.size() || h.size() < 2) {
    throw std::invalid_argument(fmt::format(
        "fitted_order: need two or more (h, error) pairs, got {} and {}", h.size(), error.size()));
  }
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t k = 0; k < h.size(); ++k) {
    if (!(h[k] > 0.0) || !(error[k] > 0.0)) {
      throw std::invalid_argument(fmt::format(
          "fitted_order: h and error must be > 0, got h = {}, error = {}", h[k], error[k]));
    }
    const double lx = std::log(h[k]), ly = std::log(error[k]);
    sx += lx;
    sy += ly;
    sxx += lx * lx;
    sxy += lx * ly;
  }
  const double n = static_cast<double>(h.size());
  const double denom = n * sxx - sx * sx;
  if (!(std::abs(denom) > 0.0)) {
    throw std::invalid_argument("fitted_order: all cell sizes are equal");
  }
  return (n * sxy - sx * sy) / denom;
}

}  // namespace shatter::verification
