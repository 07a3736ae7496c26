#include "shatter/core/solver_inputs.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace shatter {

void check_solver_inputs(const ParticleStore& particles, const std::vector<MaterialPtr>& materials,
                         std::initializer_list<Field> required) {
  for (const Field f : required) {
    if (!particles.has(f)) {
      throw std::invalid_argument(fmt::format("particles lack the '{}' column", name_of(f)));
    }
  }
  if (particles.size() == 0) throw std::invalid_argument("the scene has no particles");
  for (const Group& g : particles.groups()) {
    if (g.material < 0 || static_cast<std::size_t>(g.material) >= materials.size() ||
        !materials[static_cast<std::size_t>(g.material)]) {
      throw std::invalid_argument(fmt::format("particle group uses material {} but {} are defined",
                                              g.material, materials.size()));
    }
  }
  const auto m = particles.col(Field::mass), r = particles.col(Field::rho);
  for (std::size_t p = 0; p < particles.size(); ++p) {
    if (!(m[p] > 0.0 && std::isfinite(m[p])) || !(r[p] > 0.0 && std::isfinite(r[p]))) {
      throw std::invalid_argument(fmt::format(
          "particle {} has non-physical mass {} kg or density {} kg/m^3 (both must be > 0)", p,
          m[p], r[p]));
    }
  }
}

void check_new_time_step(const Clock& clk, double dt_min, std::string_view why_not_finite) {
  if (!std::isfinite(clk.dt)) {
    throw NumericalError(
        fmt::format("time step is not finite at step {} ({})", clk.step, why_not_finite), 0,
        clk.step);
  }
  if (clk.dt < dt_min) {
    throw NumericalError(
        fmt::format(
            "time step collapsed to {:.3e} s (< dt_min = {:.3e} s) at step {}, t = {:.6e} s",
            clk.dt, dt_min, clk.step, clk.time),
        0, clk.step);
  }
}

}  // namespace shatter
