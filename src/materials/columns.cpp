#include <stdexcept>
#include <string>

#include "materials/composed_model.hpp"

namespace shatter::materials {

namespace {
double* need(ParticleStore& s, Field f) {
  return s.col(f).data();
}  // throws naming f
}  // namespace

constitutive::ConstitutiveColumns gather_columns(ParticleStore& s, FieldSet needed,
                                                 bool increments) {
  constitutive::ConstitutiveColumns c;
  c.rho = need(s, Field::rho);
  c.mass = s.has(Field::mass) ? s.col(Field::mass).data() : nullptr;
  c.energy = need(s, Field::energy);
  constexpr Field stress[6] = {Field::sxx, Field::syy, Field::szz,
                               Field::sxy, Field::syz, Field::sxz};
  constexpr Field sdev[6] = {Field::sdev_xx, Field::sdev_yy, Field::sdev_zz,
                             Field::sdev_xy, Field::sdev_yz, Field::sdev_xz};
  constexpr Field deps[6] = {Field::deps_xx, Field::deps_yy, Field::deps_zz,
                             Field::deps_xy, Field::deps_yz, Field::deps_xz};
  constexpr Field spin[3] = {Field::dspin_xy, Field::dspin_yz, Field::dspin_xz};
  constexpr Field dmg[6] = {Field::damage,  Field::eps_min,   Field::eps_max,
                            Field::n_flaws, Field::weibull_m, Field::n_active};
  for (int k = 0; k < 6; ++k) c.stress[k] = need(s, stress[k]);
  c.pressure = need(s, Field::pressure);
  c.soundspeed = need(s, Field::soundspeed);
  if (increments) {
    for (int k = 0; k < 6; ++k) c.deps[k] = need(s, deps[k]);
    for (int k = 0; k < 3; ++k) c.dspin[k] = need(s, spin[k]);
  }
  // Model state: only the columns the model declared are read and written; a registered column
  // the model does not own (say, damage of a group without a damage model) is left alone.
  for (int k = 0; k < 6; ++k) c.sdev[k] = needed.has(sdev[k]) ? need(s, sdev[k]) : nullptr;
  c.plastic_strain = needed.has(Field::plastic_strain) ? need(s, Field::plastic_strain) : nullptr;
  c.heat = needed.has(Field::heat) ? need(s, Field::heat) : nullptr;
  for (int k = 0; k < 6; ++k) c.damage_state[k] = needed.has(dmg[k]) ? need(s, dmg[k]) : nullptr;
  c.distension = needed.has(Field::distension) ? need(s, Field::distension) : nullptr;
  c.compaction_heat =
      needed.has(Field::compaction_heat) ? need(s, Field::compaction_heat) : nullptr;
  return c;
}

}  // namespace shatter::materials
