#pragma once
// App. A.2 step 7 (kinematics): velocity gradient L_ij = sum_I v_iI dN_I/dx_j from the remapped
// nodal velocities, strain increment deps = dt sym(L) (Eq. 21) and spin increment
// dW = dt skew(L) (Eq. 23), and the density update rho^{n+1} = rho^n / (1 + tr deps).

#include <cstdint>
#include <span>

#include "mpm/stencil.hpp"

namespace shatter::kernels {

struct GradientParticles {
  const double *x, *y, *z, *size0;
  double* rho;
  double *exx, *eyy, *ezz, *exy, *eyz, *exz;  // strain increment (tensor components)
  double *wxy, *wyz, *wxz;                    // spin increment, W_ij = (L_ij - L_ji) dt / 2
  double* vgrad[9];  // APIC: L itself (1/s, row-major) becomes C_p; null for FLIP
  double inv_h;
  double dt;
  StencilCache stencil;  // kLoad: the stencils P2G stored this step
};

// Node fields a velocity-gradient window holds: the velocity p*.
using GradientWindow = NodeWindow<3>;

// Grid velocity in p*: after the MUSL remap (FLIP), or straight from the grid update (APIC).
// Particles of one owner block that share one neighbour list; the window is the caller's scratch.
template <class Shape>
void velocity_gradient_block(const GradientParticles& in, std::span<const std::uint32_t> particles,
                             const SparseGrid::Coord& owner, const std::uint32_t* neighbours,
                             const SparseGrid::Nodes& nodes, GradientWindow& win) {
  constexpr int W = Shape::kWidth;
  const double* fields[3] = {nodes.px.data(), nodes.py.data(), nodes.pz.data()};
  win.load(neighbours, fields, 3);
  const double(&v)[3][GradientWindow::kSize] = win.v;
  Stencil<Shape> st;
  for (const std::uint32_t p : particles) {
    const double xi[3] = {in.x[p] * in.inv_h, in.y[p] * in.inv_h, in.z[p] * in.inv_h};
    st.prepare(in.stencil, p, xi, 0.5 * in.size0[p] * in.inv_h, owner);
    double L[3][3] = {};
    for (int a = 0; a < W; ++a) {
      for (int b = 0; b < W; ++b) {
        const int row = GradientWindow::row(st, a, b);
        for (int c = 0; c < W; ++c) {
          const int i = row + c;
          const double g[3] = {st.dw[0][a] * st.w[1][b] * st.w[2][c],
                               st.w[0][a] * st.dw[1][b] * st.w[2][c],
                               st.w[0][a] * st.w[1][b] * st.dw[2][c]};
          const double u[3] = {v[0][i], v[1][i], v[2][i]};
          for (int r = 0; r < 3; ++r) {
            for (int q = 0; q < 3; ++q) L[r][q] += u[r] * g[q];
          }
        }
      }
    }
    if (in.vgrad[0] != nullptr) {
      for (int r = 0; r < 3; ++r) {
        for (int q = 0; q < 3; ++q) in.vgrad[3 * r + q][p] = in.inv_h * L[r][q];
      }
    }
    const double k = in.dt * in.inv_h;
    in.exx[p] = k * L[0][0];
    in.eyy[p] = k * L[1][1];
    in.ezz[p] = k * L[2][2];
    in.exy[p] = 0.5 * k * (L[0][1] + L[1][0]);
    in.eyz[p] = 0.5 * k * (L[1][2] + L[2][1]);
    in.exz[p] = 0.5 * k * (L[0][2] + L[2][0]);
    in.wxy[p] = 0.5 * k * (L[0][1] - L[1][0]);
    in.wyz[p] = 0.5 * k * (L[1][2] - L[2][1]);
    in.wxz[p] = 0.5 * k * (L[0][2] - L[2][0]);
    in.rho[p] /= 1.0 + k * (L[0][0] + L[1][1] + L[2][2]);  // App. A.2 step 7
  }
}

}  // namespace shatter::kernels
