#include "shatter/verification/neo_hookean.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace shatter::verification {

UniaxialNeoHookean::UniaxialNeoHookean(double density, double young, double poisson)
    : rho0_(density) {
  if (!(density > 0.0) || !std::isfinite(density)) {
    throw std::invalid_argument(fmt::format("neo_hookean: density must be > 0, got {}", density));
  }
  if (!(young > 0.0) || !std::isfinite(young)) {
    throw std::invalid_argument(fmt::format("neo_hookean: young must be > 0, got {}", young));
  }
  if (!(poisson >= 0.0 && poisson < 0.5)) {
    throw std::invalid_argument(
        fmt::format("neo_hookean: poisson must be in [0, 0.5), got {}", poisson));
  }
  lambda_ = young * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson));
  mu_ = young / (2.0 * (1.0 + poisson));
}

double UniaxialNeoHookean::axial_stress(double F) const {
  return lambda_ * std::log(F) / F + mu_ * (F - 1.0 / F);
}

double UniaxialNeoHookean::lateral_stress(double F) const {
  return lambda_ * std::log(F) / F;
}

double UniaxialNeoHookean::tangent(double F) const {
  return mu_ * (1.0 + 1.0 / (F * F)) + lambda_ * (1.0 - std::log(F)) / (F * F);
}

double UniaxialNeoHookean::wave_speed(double F) const {
  return F * std::sqrt(tangent(F) / rho0_);
}

void UniaxialNeoHookean::initialise(ParticleStore& store, Range range) const {
  const auto rho = store.col(Field::rho);
  for (std::size_t p = range.begin; p < range.end; ++p) {
    const double F = rho0_ / rho[p];
    store.col(Field::sxx)[p] = axial_stress(F);
    store.col(Field::syy)[p] = store.col(Field::szz)[p] = lateral_stress(F);
    store.col(Field::sxy)[p] = store.col(Field::syz)[p] = store.col(Field::sxz)[p] = 0.0;
    store.col(Field::pressure)[p] = -(axial_stress(F) + 2.0 * lateral_stress(F)) / 3.0;
    store.col(Field::soundspeed)[p] = wave_speed(F);
  }
}

// A hyperelastic stress is a function of the current F, not of its history, so there is no
// Jaumann rotation to integrate (Eq. 35 applies to rate forms); rotations are absent in
// uniaxial strain anyway. The engine has already set rho^{n+1} (App. A.2 step 7).
void UniaxialNeoHookean::update(ParticleStore& store, Range range,
                                const ConstitutiveContext& ctx) const {
  const double* rho = store.col(Field::rho).data();
  const IncrementViews inc = increments_of(store, ctx);
  const double* const* de = inc.deps;
  double* sig[3] = {store.col(Field::sxx).data(), store.col(Field::syy).data(),
                    store.col(Field::szz).data()};
  double* energy = store.col(Field::energy).data();
  double* pressure = store.col(Field::pressure).data();
  double* cs = store.col(Field::soundspeed).data();
  for (std::size_t p = range.begin; p < range.end; ++p) {
    const double F = rho0_ / rho[p];
    const double s_new[3] = {axial_stress(F), lateral_stress(F), lateral_stress(F)};
    // Specific internal energy with the mid-step stress and density (App. A.2 step 7), as the
    // engine's linear elastic model does, so the energy accounts stay comparable.
    const std::size_t q = p - inc.begin;
    const double tr = de[0][q] + de[1][q] + de[2][q];
    const double rho_old = rho[p] * (1.0 + tr);
    double work = 0.0;
    for (int k = 0; k < 3; ++k) work += 0.5 * (sig[k][p] + s_new[k]) * de[k][q];
    energy[p] += work / (0.5 * (rho_old + rho[p]));
    for (int k = 0; k < 3; ++k) sig[k][p] = s_new[k];
    pressure[p] = -(s_new[0] + s_new[1] + s_new[2]) / 3.0;
    cs[p] = wave_speed(F);
  }
}

}  // namespace shatter::verification
