#pragma once
// Value-type helpers shared by the constitutive kernels. Every kernel is a template over T, which
// is either double (the scalar reference path) or xsimd::batch<double> (the SIMD path); these
// overloads give both the same vocabulary so that kernel code never branches on T's values.

#include <cmath>
#include <cstddef>
#include <type_traits>

#include <xsimd/xsimd.hpp>

// GCC 12 reports -Wmaybe-uninitialized inside the AVX-512 intrinsics that pass
// _mm512_undefined_pd() as the masked-off source (GCC PR 105593, fixed in GCC 13) wherever they
// are inlined into our kernels. The value is never read; the warning is silenced for the
// constitutive kernels only (the pragma is consulted along the inlining chain).
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ < 13
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif

namespace shatter::simd {

using Batch = xsimd::batch<double>;
inline constexpr std::size_t kWidth = Batch::size;

template <class T>
inline constexpr bool kIsBatch = !std::is_same_v<T, double>;

// Branch-free choice: where c holds, a, else b.
inline double vselect(bool c, double a, double b) {
  return c ? a : b;
}
template <class A>
inline xsimd::batch<double, A> vselect(const xsimd::batch_bool<double, A>& c,
                                       const xsimd::batch<double, A>& a,
                                       const xsimd::batch<double, A>& b) {
  return xsimd::select(c, a, b);
}

// max/min with the same NaN-free semantics on both paths (operands are finite by construction).
inline double vmax(double a, double b) {
  return a < b ? b : a;
}
inline double vmin(double a, double b) {
  return a > b ? b : a;
}
template <class A>
inline xsimd::batch<double, A> vmax(const xsimd::batch<double, A>& a,
                                    const xsimd::batch<double, A>& b) {
  return xsimd::max(a, b);
}
template <class A>
inline xsimd::batch<double, A> vmin(const xsimd::batch<double, A>& a,
                                    const xsimd::batch<double, A>& b) {
  return xsimd::min(a, b);
}

inline double vsqrt(double a) {
  return std::sqrt(a);
}
// The SIMD lanes' exp (xsimd), so the scalar tail gives a particle the bits a batch would: the
// tail's members depend on store positions, which differ between rank counts (docs/mpi.md).
inline double vexp(double a) {
  return xsimd::exp(xsimd::batch<double>(a)).get(0);
}
inline double vabs(double a) {
  return std::fabs(a);
}
// log and pow through the SIMD lanes too (the porosity stage, kernels/porosity), for the same
// reason as vexp.
inline double vlog(double a) {
  return xsimd::log(xsimd::batch<double>(a)).get(0);
}
inline double vpow(double a, double b) {
  return xsimd::pow(xsimd::batch<double>(a), xsimd::batch<double>(b)).get(0);
}
// Whether any lane holds: lets a stage skip work no lane of a batch needs (the P-alpha solve).
inline bool any(bool c) {
  return c;
}
template <class A>
inline xsimd::batch<double, A> vsqrt(const xsimd::batch<double, A>& a) {
  return xsimd::sqrt(a);
}
template <class A>
inline xsimd::batch<double, A> vexp(const xsimd::batch<double, A>& a) {
  return xsimd::exp(a);
}
template <class A>
inline xsimd::batch<double, A> vlog(const xsimd::batch<double, A>& a) {
  return xsimd::log(a);
}
template <class A>
inline xsimd::batch<double, A> vpow(const xsimd::batch<double, A>& a,
                                    const xsimd::batch<double, A>& b) {
  return xsimd::pow(a, b);
}
template <class A>
inline bool any(const xsimd::batch_bool<double, A>& c) {
  return xsimd::any(c);
}
template <class A>
inline xsimd::batch<double, A> vabs(const xsimd::batch<double, A>& a) {
  return xsimd::abs(a);
}

// Loads and stores at an arbitrary (group-range) offset: columns are aligned, ranges need not be.
template <class T>
inline T load_col(const double* p) {
  if constexpr (kIsBatch<T>) {
    return T::load_unaligned(p);
  } else {
    return *p;
  }
}
template <class T>
inline void store_col(double* p, const T& v) {
  if constexpr (kIsBatch<T>) {
    v.store_unaligned(p);
  } else {
    *p = v;
  }
}
// A column the model may not have registered reads as a constant.
template <class T>
inline T load_or(const double* p, double fallback) {
  return p != nullptr ? load_col<T>(p) : T(fallback);
}
template <class T>
inline void store_if(double* p, const T& v) {
  if (p != nullptr) store_col<T>(p, v);
}

}  // namespace shatter::simd
