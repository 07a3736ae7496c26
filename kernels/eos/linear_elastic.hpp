#pragma once
// Linear elastic (bulk) EOS, the "elastic relation" of MPM paper Sec. 3.2: p = K (rho/rho0 - 1),
// energy-independent, so c_K^2 = K / rho0 exactly (Eq. 12 with dp/dE = 0).

#include "eos/eos_common.hpp"

namespace shatter::eos {

struct LinearElasticParams {
  double rho0 = 0.0;
  double K = 0.0;  // bulk modulus, Pa
};

class LinearElastic {
 public:
  explicit LinearElastic(const LinearElasticParams& q) : q_(q) {}

  double reference_density() const { return q_.rho0; }
  double reference_c2() const { return q_.K / q_.rho0; }

  template <class T>
  EosPoint<T> evaluate(const T& rho, const T& /*E*/) const {
    return {q_.K * (rho / q_.rho0 - 1.0), T(q_.K / q_.rho0)};
  }

 private:
  LinearElasticParams q_;
};

}  // namespace shatter::eos
