#pragma once
// Linear polynomial EOS (MPM paper Sec. 3.2, in the common hydrocode form):
//   p = C0 + C1 mu + C2 mu^2 + C3 mu^3 + (C4 + C5 mu + C6 mu^2) rho0 E,  mu = rho/rho0 - 1,
// with the C2 and C6 terms dropped in expansion (mu < 0), where a quadratic term would turn the
// tension back towards compression.

#include "eos/eos_common.hpp"

namespace shatter::eos {

struct LinearPolynomialParams {
  double rho0 = 0.0;
  double C[7] = {0, 0, 0, 0, 0, 0, 0};  // C0..C3 in Pa, C4..C6 dimensionless
};

class LinearPolynomial {
 public:
  explicit LinearPolynomial(const LinearPolynomialParams& q)
      : q_(q), c2_floor_(kSoundFloor * kSoundFloor * q.C[1] / q.rho0) {}

  double reference_density() const { return q_.rho0; }
  double reference_c2() const { return q_.C[1] / q_.rho0; }

  template <class T>
  EosPoint<T> evaluate(const T& rho_in, const T& E) const {
    using simd::vmax;
    using simd::vselect;
    const double* C = q_.C;
    const double rho0 = q_.rho0;
    const T rho = vmax(rho_in, T(kMinDensityFraction * rho0));
    const T mu = rho / rho0 - 1.0;
    const auto compressed = mu >= 0.0;
    const T c2 = vselect(compressed, T(C[2]), T(0.0));
    const T c6 = vselect(compressed, T(C[6]), T(0.0));
    const T thermal = C[4] + C[5] * mu + c6 * mu * mu;
    const T p = C[0] + mu * (C[1] + mu * (c2 + C[3] * mu)) + thermal * rho0 * E;
    const T p_r =
        (C[1] + mu * (2.0 * c2 + 3.0 * C[3] * mu) + (C[5] + 2.0 * c6 * mu) * rho0 * E) / rho0;
    const T p_e = thermal * rho0;
    return {p, vmax(isentropic_c2(rho, p, p_r, p_e), T(c2_floor_))};
  }

 private:
  LinearPolynomialParams q_;
  double c2_floor_;
};

}  // namespace shatter::eos
