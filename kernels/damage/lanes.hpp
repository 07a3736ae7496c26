#pragma once
// Lane-wise helpers that let a damage policy be written once for T = double (scalar reference
// path) and T = xsimd::batch<double> (SIMD path). xsimd 8.1 has scalar overloads for the math
// functions (sqrt, cbrt, acos, ...) but not for select, so the scalar select lives here.

#include <xsimd/xsimd.hpp>

namespace shatter::damage::lanes {

// Branch-free choice per lane; for doubles the compiler emits a conditional move.
inline double select(bool cond, double a, double b) {
  return cond ? a : b;
}

template <class A>
inline xsimd::batch<double, A> select(const xsimd::batch_bool<double, A>& cond,
                                      const xsimd::batch<double, A>& a,
                                      const xsimd::batch<double, A>& b) {
  return xsimd::select(cond, a, b);
}

}  // namespace shatter::damage::lanes
