#pragma once
// The cubic-spline (M4) smoothing kernel in three dimensions (Monaghan & Lattanzio 1985,
// A&A 149, 135, Eq. 21; the kernel Benz & Asphaug 1995 use, Sec. 4.1), with support 2h:
//   W(r, h) = sigma (1 - 3/2 q^2 + 3/4 q^3)   0 <= q < 1
//           = sigma (2 - q)^3 / 4             1 <= q < 2,   q = r / h, sigma = 1 / (pi h^3)
//           = 0                               q >= 2.
// Hot loops only: no I/O, no allocation.

#include "constitutive/simd.hpp"

namespace shatter::kernels::sph {

inline constexpr double kPi = 3.14159265358979323846;
// Support radius in units of h.
inline constexpr double kSupport = 2.0;

// W(r, h).
inline double cubic_w(double r, double h) {
  const double q = r / h;
  const double sigma = 1.0 / (kPi * h * h * h);
  if (q < 1.0) return sigma * (1.0 - 1.5 * q * q + 0.75 * q * q * q);
  if (q < 2.0) {
    const double t = 2.0 - q;
    return sigma * 0.25 * t * t * t;
  }
  return 0.0;
}

// dW/dr (r, h).
inline double cubic_dw(double r, double h) {
  const double q = r / h;
  const double sigma = 1.0 / (kPi * h * h * h * h);
  if (q < 1.0) return sigma * (-3.0 * q + 2.25 * q * q);
  if (q < 2.0) {
    const double t = 2.0 - q;
    return -0.75 * sigma * t * t;
  }
  return 0.0;
}

// (1/r) dW/dr, so that grad_i W_ij = F (x_i - x_j). Finite at r = 0 (the inner branch has no
// division), so coincident points give a zero gradient instead of 0/0.
inline double cubic_f(double r, double h) {
  const double q = r / h;
  const double s = 1.0 / (kPi * h * h * h * h * h);
  if (q < 1.0) return s * (-3.0 + 2.25 * q);
  if (q < 2.0) {
    const double t = 2.0 - q;
    return -0.75 * s * t * t / q;
  }
  return 0.0;
}

// cubic_f without branches, for T = double or a SIMD batch (the gather passes' lanes): both
// branches are evaluated and the one q falls in is selected, with one division for both 1 / h
// and 1 / q = h / r (from 1 / (h r)), so the result differs from cubic_f by a few ulp (tested in
// tests/unit/sph/cubic_spline_test.cpp). At r = 0 it returns 0, not cubic_f's finite inner
// value: the gradient F x_ij is zero there either way, which is all the passes use it for.
template <class T>
inline T cubic_f_lanes(const T& r, const T& h) {
  const T inv_hr = T(1.0) / (h * r);
  const T inv_h = r * inv_hr;
  const T q = r * inv_h;
  const T inv_h2 = inv_h * inv_h;
  const T s = inv_h2 * inv_h2 * inv_h * T(1.0 / kPi);
  const T inner = s * (T(-3.0) + T(2.25) * q);
  const T t = T(2.0) - q;
  const T outer = T(-0.75) * s * t * t * (h * h * inv_hr);
  // r = 0: inv_hr = inf, q = NaN, and neither comparison holds.
  return simd::vselect(q < T(1.0), inner, simd::vselect(q < T(2.0), outer, T(0.0)));
}

}  // namespace shatter::kernels::sph
