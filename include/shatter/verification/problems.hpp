#pragma once
// Verification problems with exact solutions (shared/reference/verification-problems.md,
// problems 1 and 2). Each runner builds the scene at a given resolution and shape function, runs
// it with the MUSL engine and returns error norms against the exact solution and the wall time,
// so that tests can bound the error and the convergence study can plot error against run time.

#include <cstddef>
#include <cstdint>
#include <span>

#include "shatter/core/config.hpp"

namespace shatter::verification {

// Problem 1: axially vibrating elastic bar, fixed at x = 0 and free at x = L. Run as a 3D bar one
// cell thick (one point across, 2 along x per cell) between slip planes in y and z, with
// Poisson 0 so that the 1D solution is exact.
struct VibratingBar {
  double young = 100.0;  // Pa
  double density = 1.0;  // kg/m^3
  double length = 25.0;  // m
  double v0 = 0.1;       // m/s, velocity amplitude
  int mode = 1;          // n in beta = (2n - 1) pi / (2L)
  // Run time in periods T = 2 pi / omega: the reference's 5 periods plus 1/8, so that neither u
  // (~ sin omega t) nor v (~ cos omega t) is at a zero of its time factor at the end, where a
  // solution of the wrong sign or amplitude would still look right.
  double periods = 5.125;
  int points_per_cell = 2;
  // Condition at x = 0. `fixed` zeroes the nodes on and beyond the plane; `symmetry` makes the
  // grid velocity odd about it, which is also u = 0 there (the exact u is odd about x = 0) but
  // leaves the slope free for 3-node stencils.
  BoundaryKind wall = BoundaryKind::fixed;

  double beta() const;
  double omega() const;
  double period() const;
  // Exact solution (Euler-Bernoulli free-fixed bar): velocity, displacement and centre-of-mass
  // velocity v0 (1 - cos(beta L)) / (beta L) cos(omega t).
  double velocity(double x, double t) const;
  double displacement(double x, double t) const;
  double centre_of_mass_velocity(double t) const;
};

// Problem 2: method of manufactured solutions on [0, L] with u(X, t) = G sin(pi X / L) sin(c pi
// t / L), c = sqrt(E / rho0), a uniaxial neo-Hookean solid and the body force that makes u exact.
struct ManufacturedSolution {
  double young = 1e7;  // Pa
  double poisson = 0.0;
  double density = 1000.0;  // kg/m^3, reference
  double length = 1.0;      // m
  double amplitude = 1e-4;  // G, m: 1e-4 small, 0.05 large deformation
  double t_end = 0.02;      // s
  int points_per_cell = 2;
  // Condition at X = 0 and X = L (u is odd about both, so `symmetry` is also exact; see
  // VibratingBar::wall).
  BoundaryKind wall = BoundaryKind::fixed;

  double wave_speed() const;  // c = sqrt(E / rho0)
  double displacement(double X, double t) const;
  double velocity(double X, double t) const;
  double acceleration(double X, double t) const;
  double deformation_gradient(double X, double t) const;  // F = 1 + du/dX
  // b = d2u/dt2 - (1/rho0) dP/dX, per unit mass (from rho0 u_tt = dP/dX + rho0 b).
  double body_force(double X, double t) const;
};

struct RunSettings {
  int cells = 32;  // cells along the bar
  ShapeKind shape = ShapeKind::ugimp;
  int threads = 1;
  double cfl = 0.3;
  TransferKind transfer = TransferKind::flip;
  double pic_fraction = 0.0;  // SolverConfig::pic_fraction (flip only)
  int xpic_order = 5;         // SolverConfig::xpic_order (xpic only)
  int fmpm_order = 5;         // SolverConfig::fmpm_order (fmpm only)
  int filter_every = 1;       // SolverConfig::filter_every (xpic and fmpm only)
};

// What a run cost, reported with its errors.
struct RunCost {
  double cell_size = 0.0;
  double wall_s = 0.0;  // set-up and run
  std::uint64_t steps = 0;
  std::size_t particles = 0;
};

struct BarErrors : RunCost {
  // Centre-of-mass velocity against exact over every step, relative to its amplitude
  // v0 (1 - cos(beta L)) / (beta L): the maximum and the root mean square.
  double com_velocity_max = 0.0;
  double com_velocity_rms = 0.0;
  // Mass-weighted L2 error at the end, relative to the amplitudes v0 / omega and v0.
  double displacement_l2 = 0.0;
  double velocity_l2 = 0.0;
  // Largest |Simulation::energy().error()| over every step: the bar loses no energy through its
  // clamped end, so this is the integrator's error plus any mis-booked boundary work.
  double energy_error_max = 0.0;
};

struct MmsErrors : RunCost {
  // Mass-weighted L2 displacement error sqrt(sum m (u_p - u(X_p))^2 / sum m), in m: at t_end
  // and the largest over all steps.
  double displacement_l2 = 0.0;
  double displacement_l2_max = 0.0;
  // The unresolved share of the kinetic energy (EnergyBudget::unresolved_kinetic over
  // transferred_kinetic, issue 16): at t_end, and over the run as the ratio of the two energies'
  // time integrals (the kinetic energy passes through zero twice a period, where the share of
  // one step means little).
  double unresolved_fraction = 0.0;
  double unresolved_fraction_run = 0.0;
};

BarErrors run_vibrating_bar(const VibratingBar& problem, const RunSettings& run);
MmsErrors run_manufactured_solution(const ManufacturedSolution& problem, const RunSettings& run);

// Least-squares slope of log(error) against log(h): the observed order of convergence. Throws
// std::invalid_argument for fewer than two points or a non-positive value.
double fitted_order(std::span<const double> h, std::span<const double> error);

}  // namespace shatter::verification
