#include "shatter/material/linear_elastic.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "strength/jaumann.hpp"

namespace shatter {

LinearElastic::LinearElastic(double density, double young, double poisson)
    : rho0_(density), young_(young), poisson_(poisson) {
  if (!(density > 0.0) || !std::isfinite(density)) {
    throw std::invalid_argument(
        fmt::format("linear_elastic: density must be > 0, got {}", density));
  }
  if (!(young > 0.0) || !std::isfinite(young)) {
    throw std::invalid_argument(fmt::format("linear_elastic: young must be > 0, got {}", young));
  }
  if (!(poisson >= 0.0 && poisson < 0.5)) {
    throw std::invalid_argument(
        fmt::format("linear_elastic: poisson must be in [0, 0.5), got {}", poisson));
  }
  bulk_ = young / (3.0 * (1.0 - 2.0 * poisson));
  shear_ = young / (2.0 * (1.0 + poisson));
}

double LinearElastic::longitudinal_speed(double rho) const {
  return std::sqrt((bulk_ + 4.0 * shear_ / 3.0) / rho);
}

void LinearElastic::initialise(ParticleStore& store, Range range) const {
  auto rho = store.col(Field::rho);
  auto c = store.col(Field::soundspeed);
  auto pr = store.col(Field::pressure);
  auto sxx = store.col(Field::sxx), syy = store.col(Field::syy), szz = store.col(Field::szz);
  for (std::size_t p = range.begin; p < range.end; ++p) {
    c[p] = longitudinal_speed(rho[p]);
    pr[p] = -(sxx[p] + syy[p] + szz[p]) / 3.0;
  }
}

void LinearElastic::update(ParticleStore& store, Range range,
                           const ConstitutiveContext& ctx) const {
  double* sig[6] = {store.col(Field::sxx).data(), store.col(Field::syy).data(),
                    store.col(Field::szz).data(), store.col(Field::sxy).data(),
                    store.col(Field::syz).data(), store.col(Field::sxz).data()};
  const IncrementViews inc = increments_of(store, ctx);
  const double* const* de = inc.deps;
  const double* const* dw = inc.dspin;
  const double* rho = store.col(Field::rho).data();
  double* energy = store.col(Field::energy).data();
  double* pressure = store.col(Field::pressure).data();
  double* cs = store.col(Field::soundspeed).data();
  const double lambda = bulk_ - 2.0 * shear_ / 3.0;
  const double two_g = 2.0 * shear_;

  tbb::parallel_for(tbb::blocked_range<std::size_t>(range.begin, range.end, 1024),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t p = r.begin(); p < r.end(); ++p) {
                        double s[6], e[6];
                        const std::size_t q = p - inc.begin;
                        for (int k = 0; k < 6; ++k) s[k] = sig[k][p], e[k] = de[k][q];
                        const double w[3] = {dw[0][q], dw[1][q], dw[2][q]};
                        double s_old[6];
                        for (int k = 0; k < 6; ++k) s_old[k] = s[k];
                        kernels::jaumann_rotate(s, w);  // Eq. 35, rotation part
                        const double tr = e[0] + e[1] + e[2];
                        // Hooke's law for the increment (Eqs. 36-37).
                        for (int k = 0; k < 3; ++k) s[k] += lambda * tr + two_g * e[k];
                        for (int k = 3; k < 6; ++k) s[k] += two_g * e[k];
                        // Energy with the mid-step stress and density (App. A.2 step 7).
                        const double rho_old = rho[p] * (1.0 + tr);
                        double s_mid[6];
                        for (int k = 0; k < 6; ++k) s_mid[k] = 0.5 * (s_old[k] + s[k]);
                        energy[p] += kernels::contract(s_mid, e) / (0.5 * (rho_old + rho[p]));
                        for (int k = 0; k < 6; ++k) sig[k][p] = s[k];
                        pressure[p] = -(s[0] + s[1] + s[2]) / 3.0;
                        cs[p] = longitudinal_speed(rho[p]);
                      }
                    });
}

}  // namespace shatter
