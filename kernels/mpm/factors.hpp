#pragma once
// The node factors of one stencil, four nodes per vector: N = (w_x w_y) w_z and, for the force,
// g_x = (w'_x w_y) w_z, g_y = (w_x w'_y) w_z and g_z = (w_x w_y) w'_z, per (a, b) four lanes over
// c (the last ones zero). They are the products of the transfers' node loops, in their order, so
// the same bits; computed W nodes per vector instead of one scalar product per node, and read
// back in the node loop as a broadcast from memory (a load) instead of a scalar product and a
// register broadcast (two ALU operations). P2G's scatter: 1.17-1.22x (bench_p2g); G2P's gather,
// whose node loop is one chain of FMAs, 0.90-0.97x, so not used there (docs/performance.md,
// "Session 21: MPM").

#include "mpm/lanes.hpp"

namespace shatter::kernels {

template <int W>
struct NodeFactors {
  static_assert(W == 2 || W == 3);
  alignas(32) double v[W * W][4][4];  // [a W + b][N, gx, gy, gz][c]

  // kGrad false: N only.
  template <bool kGrad, class St>
  void fill(const St& st) {
    const Lanes<4> wz = Lanes<4>::set(st.w[2][0], st.w[2][1], W > 2 ? st.w[2][W - 1] : 0.0, 0.0);
    const Lanes<4> dz =
        kGrad ? Lanes<4>::set(st.dw[2][0], st.dw[2][1], W > 2 ? st.dw[2][W - 1] : 0.0, 0.0)
              : Lanes<4>::zero();
    for (int a = 0; a < W; ++a) {
      for (int b = 0; b < W; ++b) {
        const double wab = st.w[0][a] * st.w[1][b];
        double(&f)[4][4] = v[a * W + b];
        (Lanes<4>::splat(wab) * wz).store(f[0]);
        if constexpr (!kGrad) continue;
        (Lanes<4>::splat(st.dw[0][a] * st.w[1][b]) * wz).store(f[1]);
        (Lanes<4>::splat(st.w[0][a] * st.dw[1][b]) * wz).store(f[2]);
        (Lanes<4>::splat(wab) * dz).store(f[3]);
      }
    }
  }
};

}  // namespace shatter::kernels
