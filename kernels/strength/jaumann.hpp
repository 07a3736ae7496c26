#pragma once
// Objective update of the deviatoric stress (MPM paper Eqs. 22, 35, 36):
//   s^{n+1}* = s^n + (W s^n - s^n W) + 2G (deps - tr(deps)/3 I),
// with W = (L - L^T)/2 dt the spin increment (skew, so W s + s W^T = W s - s W).

namespace shatter::strength {

// s: deviator (Voigt xx, yy, zz, xy, yz, xz), updated in place to the elastic trial s*.
// de: strain increment (Voigt, tensor shear components), w: spin increment (xy, yz, xz).
// G is a double, or a batch when the modulus differs lane by lane (incremental damage coupling,
// kernels/constitutive/composed_kernel.hpp: (1 - D) G per particle).
template <class T, class Mod = double>
inline void jaumann_trial(T (&s)[6], const T (&de)[6], const T (&w)[3], const Mod& G) {
  const T& wxy = w[0];
  const T& wyz = w[1];
  const T& wxz = w[2];
  // Rotation term R = W s - s W (Eq. 22), symmetric and traceless for symmetric s.
  const T rxx = 2.0 * (wxy * s[3] + wxz * s[5]);
  const T ryy = 2.0 * (wyz * s[4] - wxy * s[3]);
  const T rzz = -2.0 * (wxz * s[5] + wyz * s[4]);
  const T rxy = wxy * (s[1] - s[0]) + wxz * s[4] + wyz * s[5];
  const T ryz = wyz * (s[2] - s[1]) - wxy * s[5] - wxz * s[3];
  const T rxz = wxz * (s[2] - s[0]) + wxy * s[4] - wyz * s[3];
  // Eq. 37: 2G times the deviatoric strain increment.
  const T tr3 = (de[0] + de[1] + de[2]) * (1.0 / 3.0);
  const Mod g2 = 2.0 * G;
  s[0] = s[0] + rxx + g2 * (de[0] - tr3);
  s[1] = s[1] + ryy + g2 * (de[1] - tr3);
  s[2] = s[2] + rzz + g2 * (de[2] - tr3);
  s[3] = s[3] + rxy + g2 * de[3];
  s[4] = s[4] + ryz + g2 * de[4];
  s[5] = s[5] + rxz + g2 * de[5];
}

}  // namespace shatter::strength

// The same rotation as a separate step (Eqs. 22, 35), for LinearElastic
// (src/materials/linear_elastic.cpp): sigma += dW sigma - sigma dW = A + A^T with A = dW sigma
// (sigma symmetric, dW skew). Two formulas of one rotation stay on purpose: each path keeps the
// bits of its results (the composed kernel's sums above, LinearElastic's rows of A here).
namespace shatter::kernels {

// s: Voigt xx, yy, zz, xy, yz, xz (in/out); w: spin increment xy, yz, xz (W_yx = -W_xy, ...).
template <class T>
inline void jaumann_rotate(T s[6], const T w[3]) {
  const T wxy = w[0], wyz = w[1], wxz = w[2];
  // Rows of A = W sigma, W = [[0, wxy, wxz], [-wxy, 0, wyz], [-wxz, -wyz, 0]].
  const T a00 = wxy * s[3] + wxz * s[5];
  const T a01 = wxy * s[1] + wxz * s[4];
  const T a02 = wxy * s[4] + wxz * s[2];
  const T a10 = -wxy * s[0] + wyz * s[5];
  const T a11 = -wxy * s[3] + wyz * s[4];
  const T a12 = -wxy * s[5] + wyz * s[2];
  const T a20 = -wxz * s[0] - wyz * s[3];
  const T a21 = -wxz * s[3] - wyz * s[1];
  const T a22 = -wxz * s[5] - wyz * s[4];
  s[0] += a00 + a00;
  s[1] += a11 + a11;
  s[2] += a22 + a22;
  s[3] += a01 + a10;
  s[4] += a12 + a21;
  s[5] += a02 + a20;
}

// sigma : eps for symmetric tensors in Voigt order (tensor shear components).
template <class T>
inline T contract(const T a[6], const T b[6]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] +
         T(2.0) * (a[3] * b[3] + a[4] * b[4] + a[5] * b[5]);
}

}  // namespace shatter::kernels
