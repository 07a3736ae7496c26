#pragma once
// Ideal gas, p = (gamma - 1) rho E, c^2 = gamma p / rho (Eq. 12 with dp/drho = (gamma-1) E,
// dp/dE = (gamma-1) rho). Used by the Sod shock-tube verification.

#include "eos/eos_common.hpp"

namespace shatter::eos {

struct IdealGasParams {
  double rho0 = 0.0;   // reference density (only for the catalogue and initial state)
  double gamma = 0.0;  // ratio of specific heats
};

class IdealGas {
 public:
  explicit IdealGas(const IdealGasParams& q) : q_(q) {}

  double reference_density() const { return q_.rho0; }
  double reference_c2() const { return 0.0; }

  template <class T>
  EosPoint<T> evaluate(const T& rho_in, const T& E_in) const {
    using simd::vmax;
    // A gas holds no tension: E < 0 (round-off after strong expansion) is read as E = 0, which
    // gives p = 0 and c = 0, the exact vacuum limit.
    const T rho = vmax(rho_in, T(kMinDensityFraction * q_.rho0));
    const T E = vmax(E_in, T(0.0));
    const double gm1 = q_.gamma - 1.0;
    return {gm1 * rho * E, T(q_.gamma * gm1) * E};
  }

 private:
  IdealGasParams q_;
};

}  // namespace shatter::eos
