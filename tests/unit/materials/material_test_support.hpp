#pragma once
// Shared fixtures of the material-library tests: literature parameter sets and finite-difference
// helpers.

#include <cmath>

#include "eos/tillotson.hpp"
#include "shatter/core/particles.hpp"
#include "shatter/material/catalogue.hpp"

namespace shatter::test {

// Basalt of MPM paper Table 1.
inline eos::TillotsonParams basalt_tillotson() {
  return {2700.0, 26.7e9, 26.7e9, 0.5, 1.5, 487e6, 4.72e6, 18.2e6, 2000.0, 5.0, 5.0};
}

// Eq. 12 by central differences of the pressure, for checking the analytic derivatives.
template <class Eos>
double c2_by_differences(const Eos& eos, double rho, double e) {
  const double hr = 1e-6 * rho;
  const double he = 1e-6 * (std::abs(e) + 1e3);
  const double dp_dr = (eos.template evaluate<double>(rho + hr, e).p -
                        eos.template evaluate<double>(rho - hr, e).p) /
                       (2.0 * hr);
  const double dp_de = (eos.template evaluate<double>(rho, e + he).p -
                        eos.template evaluate<double>(rho, e - he).p) /
                       (2.0 * he);
  const double p = eos.template evaluate<double>(rho, e).p;
  return dp_dr + p / (rho * rho) * dp_de;
}

inline MaterialSpec spec(std::string name, std::string eos, std::string strength,
                         std::map<std::string, double> params) {
  MaterialSpec s;
  s.name = std::move(name);
  s.source = "test";
  s.eos = std::move(eos);
  s.strength = std::move(strength);
  s.params = std::move(params);
  return s;
}

// The columns the engine gives every material model (state, stress, increments), beside the
// model's own fields().
inline constexpr FieldSet kEngineFields{
    Field::mass,       Field::rho,     Field::energy,   Field::sxx,      Field::syy,
    Field::szz,        Field::sxy,     Field::syz,      Field::sxz,      Field::pressure,
    Field::soundspeed, Field::deps_xx, Field::deps_yy,  Field::deps_zz,  Field::deps_xy,
    Field::deps_yz,    Field::deps_xz, Field::dspin_xy, Field::dspin_yz, Field::dspin_xz};

// n points of one group at (rho, e), mass 1e-3 kg, initialised by the model.
inline ParticleStore store_at(const MaterialModel& m, std::size_t n, double rho, double e) {
  ParticleStore s;
  s.require(kEngineFields);
  s.require(m.fields());
  s.add_group(0, n);
  for (std::size_t i = 0; i < n; ++i) {
    s.col(Field::rho)[i] = rho;
    s.col(Field::energy)[i] = e;
    s.col(Field::mass)[i] = 1e-3;
  }
  m.initialise(s, {0, n});
  return s;
}

}  // namespace shatter::test
