// Step 7 of the SPH step (include/shatter/sph/solver.hpp): the energies at t^{n+1} and the next
// time step; and the finite-state check that opens step 5.

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "shatter/core/solver_inputs.hpp"
#include "sph/solver_impl.hpp"

namespace shatter::sph {

// Energy at t^{n+1}: the velocity synchronised with the positions and stresses,
// v^{n+1} = v^{n+1/2} + a^{n+1} dt^{n+1/2} / 2 (the first half of the next kick), and the
// internal energy with the viscous heat of that same half kick.
void SphSolver::Impl::energy() {
  const ParticleStore& P = s.particles_;
  const auto m = P.col(Field::mass), e = P.col(Field::energy);
  const auto vx = P.col(Field::vx), vy = P.col(Field::vy), vz = P.col(Field::vz);
  const auto x = P.col(Field::x), y = P.col(Field::y), z = P.col(Field::z);
  const double half = 0.5 * s.clock_.dt_prev;
  const Vec3 g = s.config_.gravity;
  EnergyBudget& E = s.energy_;
  E.kinetic = deterministic_sum(P.size(), [&](std::size_t p) {
    const double u = vx[p] + half * ax[p], v = vy[p] + half * ay[p], w = vz[p] + half * az[p];
    return 0.5 * m[p] * (u * u + v * v + w * w);
  });
  E.internal =
      deterministic_sum(P.size(), [&](std::size_t p) { return m[p] * (e[p] + half * heat[p]); });
  E.potential = deterministic_sum(P.size(), [&](std::size_t p) {
    return -m[p] * (g.x() * x[p] + g.y() * y[p] + g.z() * z[p]);
  });
  E.scale = std::max(E.scale, std::abs(E.kinetic) + std::abs(E.internal));
}

// Time step (Monaghan 1992, Sec. 4; Monaghan 1989, J. Comput. Phys. 82, 1): the Courant
// condition with the viscous signal speed, dt_c = cfl h / (c + 1.2 (alpha c + beta max mu)),
// and the force condition dt_f = cfl sqrt(h / |a|). c is the longitudinal speed c_p the
// material model stores (damage included). Both minima are exact, so any thread count gives
// the same dt. Unlike MPM's Eq. 34 there is no |v|: SPH has no grid to outrun.
double SphSolver::Impl::stable_dt() const {
  const ParticleStore& P = s.particles_;
  const auto c = P.col(Field::soundspeed);
  // With the switch, the largest alpha it can reach (and beta = 2 alpha): the step does not
  // depend on the switch's state and is that of the constant default at alpha_max = 1.
  const double a_visc = switch_on ? s.sph_.alpha_max : s.sph_.alpha;
  const double b_visc = switch_on ? 2.0 * s.sph_.alpha_max : s.sph_.beta;
  const double cfl = s.config_.cfl;
  const double inf = std::numeric_limits<double>::infinity();
  const double* mu = h_mid.data();  // max_j |mu_ij| from the forces pass (solver_impl.hpp)
  const double dt = exact_min(P.size(), inf, [&](std::size_t p) {
    const double sig = c[p] + 1.2 * (a_visc * c[p] + b_visc * mu[p]);
    const double dt_c = sig > 0.0 ? cfl * h[p] / sig : inf;
    const double a = std::sqrt(ax[p] * ax[p] + ay[p] * ay[p] + az[p] * az[p]);
    const double dt_f = a > 0.0 ? cfl * std::sqrt(h[p] / a) : inf;
    return std::min(dt_c, dt_f);
  });
  return std::min(dt, s.config_.dt_max);
}

void SphSolver::Impl::next_dt() {
  Clock& clk = s.clock_;
  clk.dt = stable_dt();
  check_new_time_step(clk, s.config_.dt_min, "no sound speed, no force, and no dt_max set");
}

// The first particle (lowest index) whose state is not finite, or whose density is not
// positive, stops the run with its name, field and step.
void SphSolver::Impl::check_state() const {
  const ParticleStore& P = s.particles_;
  const std::size_t n = P.size();
  static constexpr Field kChecked[] = {Field::x,   Field::y,      Field::z,         Field::vx,
                                       Field::vy,  Field::vz,     Field::sxx,       Field::syy,
                                       Field::szz, Field::sxy,    Field::syz,       Field::sxz,
                                       Field::rho, Field::energy, Field::soundspeed};
  auto bad_value = [](Field f, double v) {
    return !std::isfinite(v) || (f == Field::rho && !(v > 0.0));
  };
  const std::size_t bad = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, n, kGrain), n,
      [&](const tbb::blocked_range<std::size_t>& r, std::size_t found) {
        for (const Field f : kChecked) {
          const auto c = P.col(f);
          for (std::size_t p = r.begin(); p < std::min(r.end(), found); ++p) {
            if (bad_value(f, c[p])) {
              found = p;
              break;
            }
          }
        }
        return found;
      },
      [](std::size_t a, std::size_t b) { return std::min(a, b); });
  if (bad == n) return;
  for (const Field f : kChecked) {
    const double v = P.col(f)[bad];
    if (bad_value(f, v)) {
      throw NumericalError(
          fmt::format("{} {} = {} at particle {} (id {}) at step {}, t = {:.6e} s",
                      f == Field::rho && std::isfinite(v) ? "non-positive" : "non-finite",
                      name_of(f), v, bad, P.col(IField::id)[bad], s.clock_.step, s.clock_.time),
          bad, s.clock_.step);
    }
  }
}

}  // namespace shatter::sph
