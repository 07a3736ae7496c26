#pragma once
// Objective stress rotation of the Jaumann rate (Eqs. 22, 35): sigma += dW sigma - sigma dW with
// the skew spin increment dW = (L - L^T) dt / 2. Because sigma is symmetric and dW skew,
// dW sigma - sigma dW = A + A^T with A = dW sigma, which is what is computed.

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
