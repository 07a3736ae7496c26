#pragma once
// Mie–Grüneisen EOS referred to a linear Us = c0 + s up Hugoniot (Zhang et al. 2016, MPM paper
// Sec. 3.2), with Gamma rho = Gamma0 rho0:
//   chi = 1 - rho0/rho,  p_H = rho0 c0^2 chi / (1 - s chi)^2,  E_H = p_H chi / (2 rho0),
//   p = p_H + Gamma0 rho0 (E - E_H) = p_H (1 - Gamma0 chi / 2) + Gamma0 rho0 E.
// In expansion (chi < 0) the reference curve is the linear p_H = rho0 c0^2 chi.

#include "eos/eos_common.hpp"

namespace shatter::eos {

struct MieGruneisenParams {
  double rho0 = 0.0;    // kg/m^3
  double c0 = 0.0;      // m/s, bulk sound speed (Us intercept)
  double s = 0.0;       // -, Us-up slope
  double gamma0 = 0.0;  // -, Grüneisen parameter at rho0
};

class MieGruneisen {
 public:
  // The linear Hugoniot is singular at chi = 1/s (infinite pressure). Beyond kChiFraction / s the
  // reference curve continues as its tangent (C1), so p and c stay finite in runaway compression;
  // 0.9/s is a compression rho/rho0 = 1/(1 - 0.9/s), i.e. 3.4 for s = 1.5, far beyond the range
  // a linear Us-up fit is measured over.
  static constexpr double kChiFraction = 0.9;

  explicit MieGruneisen(const MieGruneisenParams& q) : q_(q) {
    k0_ = q.rho0 * q.c0 * q.c0;
    chi_max_ = q.s > 0.0 ? kChiFraction / q.s : 1.0;
    const double d = 1.0 - q.s * chi_max_;
    ph_max_ = k0_ * chi_max_ / (d * d);
    dph_max_ = k0_ * (1.0 + q.s * chi_max_) / (d * d * d);
    c2_floor_ = kSoundFloor * kSoundFloor * q.c0 * q.c0;
  }

  double reference_density() const { return q_.rho0; }
  double reference_c2() const { return q_.c0 * q_.c0; }

  template <class T>
  EosPoint<T> evaluate(const T& rho_in, const T& E) const {
    using simd::vmax;
    using simd::vmin;
    using simd::vselect;
    const T rho = vmax(rho_in, T(kMinDensityFraction * q_.rho0));
    const T chi = 1.0 - q_.rho0 / rho;
    const T chi_c = vmin(vmax(chi, T(0.0)), T(chi_max_));
    const T d = 1.0 - q_.s * chi_c;
    // Compressed reference curve and its slope dp_H/dchi = rho0 c0^2 (1 + s chi)/(1 - s chi)^3.
    T ph = k0_ * chi_c / (d * d);
    T dph = k0_ * (1.0 + q_.s * chi_c) / (d * d * d);
    const auto beyond = chi > chi_max_;
    ph = vselect(beyond, ph_max_ + dph_max_ * (chi - chi_max_), ph);
    dph = vselect(beyond, T(dph_max_), dph);
    const auto expanded = chi < 0.0;
    ph = vselect(expanded, k0_ * chi, ph);
    dph = vselect(expanded, T(k0_), dph);

    const double g0 = q_.gamma0;
    const T p = ph * (1.0 - 0.5 * g0 * chi) + g0 * q_.rho0 * E;
    const T dchi_drho = q_.rho0 / (rho * rho);
    const T p_r = (dph * (1.0 - 0.5 * g0 * chi) - 0.5 * g0 * ph) * dchi_drho;
    const T p_e = T(g0 * q_.rho0);
    return {p, vmax(isentropic_c2(rho, p, p_r, p_e), T(c2_floor_))};
  }

 private:
  MieGruneisenParams q_;
  double k0_ = 0.0, chi_max_ = 0.0, ph_max_ = 0.0, dph_max_ = 0.0, c2_floor_ = 0.0;
};

}  // namespace shatter::eos
