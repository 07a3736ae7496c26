#pragma once
// Principal values of a symmetric 3x3 tensor in closed form (trigonometric solution of the
// characteristic cubic, Smith 1961), written once for T = double and T = xsimd::batch<double>:
// no branches on values, so it vectorises. Used for the largest tensile stress of MPM paper
// Eq. 18 / BA95 Eq. 21 and for the BA95 Sec. 4.4 static-strength pre-pass.
//
// Accuracy: going through the invariants (det, J2) costs accuracy where two eigenvalues nearly
// coincide: the error is about eps ||A|| min(||A|| / gap, eps^-1/2), i.e. ~1e-14 ||A|| for
// well-separated values and at worst ~1e-8 ||A|| at an exact double root (acos near -1). For
// Eq. 18 this is irrelevant: a relative error of 1e-8 in sigma_max changes n_act by m_p x 1e-8.
// Checked in tests/unit/fracture/principal_test.cpp against Eigen's iterative solver.

#include <numbers>

#include <xsimd/xsimd.hpp>

#include "damage/lanes.hpp"

namespace shatter::damage {

template <class T>
struct PrincipalValues {
  T s1;  // largest
  T s2;
  T s3;  // smallest
};

// s in Voigt order xx, yy, zz, xy, yz, xz.
template <class T>
inline PrincipalValues<T> principal_values(const T (&s)[6]) {
  const T q = (s[0] + s[1] + s[2]) * (1.0 / 3.0);
  const T a = s[0] - q;
  const T b = s[1] - q;
  const T c = s[2] - q;
  const T xy = s[3];
  const T yz = s[4];
  const T xz = s[5];
  const T off = xy * xy + yz * yz + xz * xz;
  // p^2 = tr(dev^2)/6: the spread of the eigenvalues about their mean q.
  const T p = xsimd::sqrt((a * a + b * b + c * c + 2.0 * off) * (1.0 / 6.0));
  const T det = a * (b * c - yz * yz) - xy * (xy * c - yz * xz) + xz * (xy * yz - b * xz);
  // An isotropic tensor (p = 0) has a triple root; any angle gives s1 = s2 = s3 = q then.
  const auto spread = p > T(1e-100);
  const T p_safe = lanes::select(spread, p, T(1.0));
  const T r = lanes::select(spread, det / (2.0 * p_safe * p_safe * p_safe), T(0.0));
  // Round-off can push |r| slightly above 1, outside acos's domain.
  const T phi = xsimd::acos(xsimd::max(T(-1.0), xsimd::min(T(1.0), r))) * (1.0 / 3.0);
  const T s1 = q + 2.0 * p * xsimd::cos(phi);
  const T s3 = q + 2.0 * p * xsimd::cos(phi + (2.0 * std::numbers::pi / 3.0));
  const T s2 = 3.0 * q - s1 - s3;
  return {s1, s2, s3};
}

template <class T>
inline T largest_principal(const T (&s)[6]) {
  return principal_values(s).s1;
}

}  // namespace shatter::damage
