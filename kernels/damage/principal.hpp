#pragma once
// Principal values of a symmetric 3x3 tensor by cyclic Jacobi rotations (Golub & Van Loan,
// Sec. 8.5), written once for T = double and T = xsimd::batch<double>: a fixed number of sweeps
// and lane-wise selects, no branch on values, only +, *, /, sqrt — so it vectorises, needs no
// trigonometric functions, and stays accurate where eigenvalues nearly coincide (the closed-form
// trigonometric solution loses half the digits there, ~1e-8 ||A||). Used for the largest tensile
// stress of MPM paper Eq. 18 / BA95 Eq. 21 and the BA95 Sec. 4.4 static-strength pre-pass.
//
// Accuracy: cyclic Jacobi converges quadratically; for 3x3 four sweeps reach round-off from any
// start, the fifth is margin. Error a few eps ||A||, checked in
// tests/unit/fracture/principal_test.cpp against Eigen's solver.

#include <xsimd/xsimd.hpp>

#include "damage/lanes.hpp"

namespace shatter::damage {

template <class T>
struct PrincipalValues {
  T s1;  // largest
  T s2;
  T s3;  // smallest
};

namespace detail {

// One rotation in the (p, q) plane that zeroes a_pq (Numerical Recipes' stable form:
// t = sgn(theta) / (|theta| + sqrt(theta^2 + 1)), theta = (a_qq - a_pp) / (2 a_pq)).
// r is the third index; a_pr and a_qr rotate with it.
template <class T>
inline void jacobi_rotate(T& app, T& aqq, T& apq, T& apr, T& aqr) {
  const auto active = apq != T(0.0);
  const T apq_safe = lanes::select(active, apq, T(1.0));
  const T theta = (aqq - app) / (2.0 * apq_safe);
  // For |theta| > 1e150, theta^2 would overflow: t -> 1 / (2 theta) there.
  const T abs_theta = xsimd::abs(theta);
  const T root = lanes::select(abs_theta < T(1e150), xsimd::sqrt(theta * theta + 1.0), abs_theta);
  const T sign = lanes::select(theta < T(0.0), T(-1.0), T(1.0));
  const T t = lanes::select(active, sign / (abs_theta + root), T(0.0));
  const T c = 1.0 / xsimd::sqrt(t * t + 1.0);
  const T s = t * c;
  app = app - t * apq;
  aqq = aqq + t * apq;
  apq = T(0.0);
  const T pr = apr;
  apr = c * pr - s * aqr;
  aqr = s * pr + c * aqr;
}

}  // namespace detail

// s in Voigt order xx, yy, zz, xy, yz, xz.
template <class T>
inline PrincipalValues<T> principal_values(const T (&s)[6]) {
  T a00 = s[0], a11 = s[1], a22 = s[2], a01 = s[3], a12 = s[4], a02 = s[5];
  for (int sweep = 0; sweep < 5; ++sweep) {
    detail::jacobi_rotate(a00, a11, a01, a02, a12);  // (0,1), third index 2
    detail::jacobi_rotate(a00, a22, a02, a01, a12);  // (0,2), third index 1
    detail::jacobi_rotate(a11, a22, a12, a01, a02);  // (1,2), third index 0
  }
  const T hi = xsimd::max(a00, xsimd::max(a11, a22));
  const T lo = xsimd::min(a00, xsimd::min(a11, a22));
  const T mid = xsimd::max(xsimd::min(a00, a11), xsimd::min(xsimd::max(a00, a11), a22));
  return {hi, mid, lo};
}

template <class T>
inline T largest_principal(const T (&s)[6]) {
  return principal_values(s).s1;
}

}  // namespace shatter::damage
