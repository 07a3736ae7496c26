#pragma once
// Lane-wise helpers that let a damage policy be written once for T = double (scalar reference
// path) and T = xsimd::batch<double> (SIMD path). xsimd 8.1 has scalar overloads for the math
// functions (sqrt, cbrt, acos, ...) but not for select: the policies use simd::vselect
// (kernels/constitutive/simd.hpp), the composed kernel's own, for both paths.

#include <cmath>

#include <xsimd/xsimd.hpp>

#include "constitutive/simd.hpp"

// GCC 12 reports -W(maybe-)uninitialized inside the AVX-512 intrinsics that pass
// _mm512_undefined_pd() as the masked-off source (GCC PR 105593, fixed in GCC 13) wherever xsimd
// math is inlined into a policy; the value is never read. Same guard as
// kernels/constitutive/simd.hpp (the pragma is consulted along the inlining chain).
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ < 13
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif

namespace shatter::damage::lanes {

// log and cbrt. xsimd 8.1's AVX-512BW log and cbrt do not compile without optimisation (GCC then
// defines the masked blend intrinsics as macros, whose casts reject xsimd's integer batches), so
// unoptimised (Debug, sanitizer) builds evaluate them lane by lane with libm.
// Optimised builds evaluate the scalar tail with the SIMD lanes' own algorithm, so a particle
// gets the same bits in a batch or in the tail: which particles form the tail depends on where
// they sit in the store, which differs between rank counts (docs/mpi.md).
inline double log(double x) {
#if defined(__OPTIMIZE__)
  return xsimd::log(xsimd::batch<double>(x)).get(0);
#else
  return std::log(x);
#endif
}
inline double cbrt(double x) {
#if defined(__OPTIMIZE__)
  return xsimd::cbrt(xsimd::batch<double>(x)).get(0);
#else
  return std::cbrt(x);
#endif
}

namespace detail {
template <class A, class F>
inline xsimd::batch<double, A> per_lane(const xsimd::batch<double, A>& x, F&& f) {
  alignas(64) double v[xsimd::batch<double, A>::size];
  x.store_aligned(v);
  for (double& e : v) e = f(e);
  return xsimd::batch<double, A>::load_aligned(v);
}
}  // namespace detail

template <class A>
inline xsimd::batch<double, A> log(const xsimd::batch<double, A>& x) {
#if defined(__OPTIMIZE__)
  return xsimd::log(x);
#else
  return detail::per_lane(x, [](double e) { return std::log(e); });
#endif
}

template <class A>
inline xsimd::batch<double, A> cbrt(const xsimd::batch<double, A>& x) {
#if defined(__OPTIMIZE__)
  return xsimd::cbrt(x);
#else
  return detail::per_lane(x, [](double e) { return std::cbrt(e); });
#endif
}

}  // namespace shatter::damage::lanes
