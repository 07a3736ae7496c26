#pragma once
// Short vectors of doubles for the gathers (G2P, velocity gradient). A gather sums, over the 27
// stencil nodes of one particle, node values times a weight; the components of one node (x, y, z
// of a field, or several fields side by side) sit in the lanes of one vector, so each node costs
// one load and one fused multiply-add instead of one per component. Lanes run across the
// components of one particle, not across particles: no gather instruction, no scalar tail, and
// each lane does exactly the IEEE operations of the scalar loop it replaces (a product, then
// fma(weight, value, sum) in node order), whatever the compiler's -ffp-contract. Results thus do
// not depend on which particles a block holds, on the thread count or on the rank count
// (docs/mpi.md, "Determinism"), and the portable fallback (std::fma per lane) gives the same bits.

#include <cmath>
#include <cstdint>

#if (defined(__AVX__) && defined(__FMA__)) || defined(__AVX512F__)
#include <immintrin.h>
#endif

namespace shatter::kernels {

// The first 64-byte boundary at or after p, for scratch arrays that hold 7 extra doubles:
// aligned by hand because GCC 12's AddressSanitizer places stack objects at 32-byte boundaries
// whatever alignas asks (and UBSan then reports the misaligned object).
inline double* align64(double* p) {
  return reinterpret_cast<double*>((reinterpret_cast<std::uintptr_t>(p) + 63) &
                                   ~std::uintptr_t{63});
}
inline const double* align64(const double* p) {
  return align64(const_cast<double*>(p));
}

// N doubles (N = 4 or 8). The portable form; the specialisations below use AVX/FMA and AVX-512.
template <int N>
struct Lanes {
  double v[N];
  static Lanes zero() { return {}; }
  static Lanes splat(double s) {
    Lanes r;
    for (int k = 0; k < N; ++k) r.v[k] = s;
    return r;
  }
  static Lanes load(const double* p) {
    Lanes r;
    for (int k = 0; k < N; ++k) r.v[k] = p[k];
    return r;
  }
  // (a, b, c, d); N = 4 only.
  static Lanes set(double a, double b, double c, double d) {
    static_assert(N == 4);
    return {{a, b, c, d}};
  }
  void store(double* p) const {
    for (int k = 0; k < N; ++k) p[k] = v[k];
  }
  friend Lanes operator*(const Lanes& a, const Lanes& b) {
    Lanes r;
    for (int k = 0; k < N; ++k) r.v[k] = a.v[k] * b.v[k];
    return r;
  }
  friend Lanes operator+(const Lanes& a, const Lanes& b) {
    Lanes r;
    for (int k = 0; k < N; ++k) r.v[k] = a.v[k] + b.v[k];
    return r;
  }
  // a * b + c, rounded once.
  friend Lanes fma(const Lanes& a, const Lanes& b, const Lanes& c) {
    Lanes r;
    for (int k = 0; k < N; ++k) r.v[k] = std::fma(a.v[k], b.v[k], c.v[k]);
    return r;
  }
};

#if defined(__AVX__) && defined(__FMA__)
template <>
struct Lanes<4> {
  __m256d v;
  static Lanes zero() { return {_mm256_setzero_pd()}; }
  static Lanes splat(double s) { return {_mm256_set1_pd(s)}; }
  static Lanes load(const double* p) { return {_mm256_loadu_pd(p)}; }
  // In registers (a store of scalars then a vector load would stall on store forwarding).
  static Lanes set(double a, double b, double c, double d) { return {_mm256_setr_pd(a, b, c, d)}; }
  void store(double* p) const { _mm256_storeu_pd(p, v); }
  friend Lanes operator*(const Lanes& a, const Lanes& b) { return {_mm256_mul_pd(a.v, b.v)}; }
  friend Lanes operator+(const Lanes& a, const Lanes& b) { return {_mm256_add_pd(a.v, b.v)}; }
  friend Lanes fma(const Lanes& a, const Lanes& b, const Lanes& c) {
    return {_mm256_fmadd_pd(a.v, b.v, c.v)};
  }
};
#endif

#if defined(__AVX512F__)
template <>
struct Lanes<8> {
  __m512d v;
  static Lanes zero() { return {_mm512_setzero_pd()}; }
  static Lanes splat(double s) { return {_mm512_set1_pd(s)}; }
  static Lanes load(const double* p) { return {_mm512_loadu_pd(p)}; }
  void store(double* p) const { _mm512_storeu_pd(p, v); }
  friend Lanes operator*(const Lanes& a, const Lanes& b) { return {_mm512_mul_pd(a.v, b.v)}; }
  friend Lanes operator+(const Lanes& a, const Lanes& b) { return {_mm512_add_pd(a.v, b.v)}; }
  friend Lanes fma(const Lanes& a, const Lanes& b, const Lanes& c) {
    return {_mm512_fmadd_pd(a.v, b.v, c.v)};
  }
};
#endif

}  // namespace shatter::kernels
