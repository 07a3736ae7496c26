#pragma once
// Simplified Tillotson EOS (Jutzi et al. 2008, as listed in MPM paper Sec. 3.2): the condensed
// branch with a constant Grüneisen factor, p = (a + b) rho E + A mu, valid for moderate shocks
// where no vaporisation occurs. Sound speed from Eq. 12 (which the constant-c0 shortcut of some
// codes omits).

#include "eos/eos_common.hpp"

namespace shatter::eos {

struct TillotsonSimplifiedParams {
  double rho0 = 0.0;  // kg/m^3
  double A = 0.0;     // Pa
  double a = 0.0;     // -
  double b = 0.0;     // -
};

class TillotsonSimplified {
 public:
  explicit TillotsonSimplified(const TillotsonSimplifiedParams& q)
      : q_(q), c2_floor_(kSoundFloor * kSoundFloor * q.A / q.rho0) {}

  double reference_density() const { return q_.rho0; }
  double reference_c2() const { return q_.A / q_.rho0; }

  template <class T>
  EosPoint<T> evaluate(const T& rho_in, const T& E_in) const {
    using simd::vmax;
    const T rho = vmax(rho_in, T(kMinDensityFraction * q_.rho0));
    const T E = vmax(E_in, T(0.0));  // referred to the cold curve E = 0, as Tillotson
    const double gam = q_.a + q_.b;
    // Tension is bounded by -A as rho -> 0, so no further floor is needed.
    const T p = gam * rho * E + q_.A * (rho / q_.rho0 - 1.0);
    const T p_r = gam * E + q_.A / q_.rho0;
    const T p_e = T(gam) * rho;
    return {p, vmax(isentropic_c2(rho, p, p_r, p_e), T(c2_floor_))};
  }

 private:
  TillotsonSimplifiedParams q_;
  double c2_floor_;
};

}  // namespace shatter::eos
