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
