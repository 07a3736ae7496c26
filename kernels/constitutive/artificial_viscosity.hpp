#pragma once
// Bulk artificial viscosity of von Neumann & Richtmyer (1950), quadratic + linear (Landshoff),
// acting on compression only:
//   q = rho (c_Q (h d)^2 + c_L c h d),  d = max(-div v, 0),  div v = tr(deps) / dt,
// with h the grid cell size. q adds to the pressure the momentum equation sees (and so does
// work on the internal energy). Its explicit stability limit is that of a diffusion with
// coefficient nu = h (c_L c + c_Q h d), dt <= h^2 / (2 nu); folded into the CFL condition
// dt = h / c_eff (Eq. 34) this is an extra signal speed 2 (c_L c + c_Q h d).

#include "constitutive/simd.hpp"

namespace shatter::constitutive {

template <class T>
struct ViscousTerm {
  T q;      // viscous pressure (Pa, >= 0)
  T speed;  // extra signal speed for the time step (m/s, >= 0)
};

template <class T>
inline ViscousTerm<T> artificial_viscosity(const T& tr_deps, double inv_dt, double h, const T& rho,
                                           const T& c, double c_linear, double c_quadratic) {
  using simd::vmax;
  const T d = vmax(-tr_deps * inv_dt, T(0.0));  // compression rate
  // Both terms vanish on expansion (d = 0), the linear one through the select: a material that
  // is not being compressed has no viscosity and no extra signal speed.
  const T lin = simd::vselect(d > 0.0, c_linear * c, T(0.0));
  const T quad = c_quadratic * h * d;
  return {rho * h * d * (lin + quad), 2.0 * (lin + quad)};
}

}  // namespace shatter::constitutive
