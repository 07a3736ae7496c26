// App. A.2 step 7b: the constitutive update of each material group (Eqs. 22, 35; EOS,
// strength, damage), one composed kernel per group (src/materials).

#include "mpm/stages/stages.hpp"
#include "mpm/state.hpp"

namespace shatter::mpm {

Stage constitutive_stage(State& s) {
  FieldSet models;
  for (const auto& m : s.materials) models = models | m->fields();
  const bool rings = s.config.geometry == Geometry::axisymmetric;  // R_s of the damage reads x
  const FieldSet ring_radius = rings ? FieldSet{Field::x} : FieldSet{};
  return {
      "constitutive",
      {kStrainIncrement | kSpinIncrement | FieldSet{Field::rho, Field::mass} | ring_radius, kClock},
      {kStress | models | FieldSet{Field::energy, Field::pressure, Field::soundspeed}, 0},
      [&s, rings] {
        const ConstitutiveContext ctx{s.dt_step, s.config.cell_size, s.config.viscosity, rings};
        for (const Group& g : s.particles.groups()) {
          if (g.range.empty()) continue;
          s.materials[static_cast<std::size_t>(g.material)]->update(s.particles, g.range, ctx);
        }
      }};
}

}  // namespace shatter::mpm
