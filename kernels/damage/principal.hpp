#pragma once
// Principal values of a symmetric 3x3 tensor by cyclic Jacobi rotations (Golub & Van Loan,
// Sec. 8.5), written once for T = double and T = xsimd::batch<double>: a fixed number of sweeps
// and lane-wise selects, no branch on values, only +, *, /, sqrt — so it vectorises, needs no
// trigonometric functions, and stays accurate where eigenvalues nearly coincide (the closed-form
// trigonometric solution loses half the digits there, ~1e-8 ||A||). Used for the largest tensile
// stress of MPM paper Eq. 18 / BA95 Eq. 21 and the BA95 Sec. 4.4 static-strength pre-pass.
//
// Accuracy: cyclic Jacobi converges quadratically; for 3x3, three sweeps leave ~1e-10 ||A|| and
// the fourth reaches round-off (measured 7 eps ||A|| worst over 2e5 random tensors and 2e4
// rotated near-double roots; tests/unit/fracture/principal_test.cpp checks against Eigen).

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

// One rotation in the (p, q) plane that zeroes a_pq: tan(2 phi) = 2 a_pq / (a_qq - a_pp), and
// t = tan(phi) from the smaller root of t^2 + 2 t / tan(2 phi) - 1 = 0 in the cancellation-free
// form t = sgn(d) h / (|d| + sqrt(d^2 + h^2)) with d = a_qq - a_pp, h = 2 a_pq (Golub & Van
// Loan's sym.schur2, written with one division). Stresses are far below 1e150 Pa, so d^2 + h^2
// cannot overflow. r is the third index; a_pr and a_qr rotate with it.
template <class T>
inline void jacobi_rotate(T& app, T& aqq, T& apq, T& apr, T& aqr) {
  const T d = aqq - app;
  const T h = 2.0 * apq;
  const T denom = xsimd::abs(d) + xsimd::sqrt(d * d + h * h);
  // denom = 0 only when the block is already diagonal and isotropic: no rotation.
  const auto active = denom > T(0.0);
  const T signed_h = simd::vselect(d < T(0.0), -h, h);
  const T t = simd::vselect(active, signed_h / simd::vselect(active, denom, T(1.0)), T(0.0));
  const T c = 1.0 / xsimd::sqrt(t * t + 1.0);
  const T s = t * c;
  app = app - t * apq;
  aqq = aqq + t * apq;
  apq = T(0.0);
  const T pr = apr;
  apr = c * pr - s * aqr;
  aqr = s * pr + c * aqr;
}

// Whether every remaining sweep would leave the diagonal unchanged, bit for bit, in every lane.
// A rotation moves a_pp and a_qq by t a_pq with |t| <= |a_pq| / |d| (denom >= 2 |d| above), so
// by at most F^2 / |d|, F^2 = a01^2 + a02^2 + a12^2 (a rotation keeps the sum of the squares of
// the off-diagonal entries it turns and zeroes a_pq, so no later a_pq exceeds F up to a few
// ulps). Below a quarter of the spacing of the doubles around a diagonal entry a (>= |a| 2^-55)
// a - t a_pq rounds back to a; with F^2 < 2^-57 min|d| min|a| that holds for every pair of
// every later sweep, with a margin of 4 for the roundings of t, the products and this test.
// The diagonal entries and their differences are bounded below (1e-100, far below any stress)
// so that no product here underflows. A NaN lane never passes. Then the diagonal after all
// four sweeps is the one now: skipping them changes no bit of the principal values.
template <class T>
inline bool diagonal_settled(const T& a00, const T& a11, const T& a22, const T& a01, const T& a02,
                             const T& a12) {
  const T f2 = a01 * a01 + a02 * a02 + a12 * a12;
  const T a_min = xsimd::min(xsimd::abs(a00), xsimd::min(xsimd::abs(a11), xsimd::abs(a22)));
  const T d_min =
      xsimd::min(xsimd::abs(a11 - a00), xsimd::min(xsimd::abs(a22 - a00), xsimd::abs(a22 - a11)));
  const auto settled =
      (f2 < T(0x1p-57) * d_min * a_min) && (a_min > T(1e-100)) && (d_min > T(1e-100));
  return !simd::any(!settled);
}

}  // namespace detail

// s in Voigt order xx, yy, zz, xy, yz, xz. After the first sweep, the rotations stop once no
// later one can change the diagonal (detail::diagonal_settled, tested after every rotation:
// its argument holds for whatever rotations follow): the same bits as four sweeps
// (kAllSweeps = true runs all twelve rotations, the reference the tests compare with).
// rotations, if given, receives the number of rotations made.
template <class T, bool kAllSweeps = false>
inline PrincipalValues<T> principal_values(const T (&s)[6], int* rotations = nullptr) {
  T a00 = s[0], a11 = s[1], a22 = s[2], a01 = s[3], a12 = s[4], a02 = s[5];
  int done = 0;
  const auto settled = [&] {
    return !kAllSweeps && done >= 3 && detail::diagonal_settled(a00, a11, a22, a01, a02, a12);
  };
  while (done < 12) {
    if (settled()) break;
    detail::jacobi_rotate(a00, a11, a01, a02, a12);  // (0,1), third index 2
    if (++done >= 4 && settled()) break;
    detail::jacobi_rotate(a00, a22, a02, a01, a12);  // (0,2), third index 1
    if (++done >= 5 && settled()) break;
    detail::jacobi_rotate(a11, a22, a12, a01, a02);  // (1,2), third index 0
    ++done;
  }
  if (rotations != nullptr) *rotations = done;
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
