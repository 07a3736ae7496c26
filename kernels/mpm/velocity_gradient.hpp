#pragma once
// App. A.2 step 7 (kinematics): velocity gradient L_ij = sum_I v_iI dN_I/dx_j from the remapped
// nodal velocities, strain increment deps = dt sym(L) (Eq. 21) and spin increment
// dW = dt skew(L) (Eq. 23), and the density update rho^{n+1} = rho^n / (1 + tr deps).

#include <cstddef>
#include <cstdint>
#include <span>

#include "mpm/lanes.hpp"
#include "mpm/stencil.hpp"

namespace shatter::kernels {

struct GradientParticles {
  const double *x, *y, *z, *size0;
  double* rho;
  double *exx, *eyy, *ezz, *exy, *eyz, *exz;  // strain increment (tensor components)
  double *wxy, *wyz, *wxz;                    // spin increment, W_ij = (L_ij - L_ji) dt / 2
  std::size_t inc_begin = 0;  // particle p's increments at index p - inc_begin (a chunk buffer)
  double* vgrad[9];           // APIC: L itself (1/s, row-major) becomes C_p; null for FLIP
  double inv_h;
  double dt;
  StencilCache stencil;  // kLoad: the stencils P2G stored this step
};

// Node fields a velocity-gradient window holds: the velocity p*.
using GradientWindow = NodeWindow<3>;

// L_ij / (1/h) = sum_I v_iI G_Ij, with G_I = (w'_x w_y w_z, w_x w'_y w_z, w_x w_y w'_z) at
// stencil node I (cell units). The three components of G_I sit in the lanes of one vector, the
// fourth holding N_I = w_x w_y w_z, formed as (A_a B_b) C_c with A_a = (w'_x, w_x, w_x, w_x),
// B_b = (w_y, w'_y, w_y, w_y), C_c = (w_z, w_z, w'_z, w_z): each lane the product of the scalar
// loop, in its order. Row r of L then adds fma(v_rI, G_I, L_r) node by node (lanes.hpp): the
// scalar loop's operations; L[r][3] is the interpolated velocity sum_I N_I v_rI (read by the
// axisymmetric mode's hoop rate; in 3-D the lane was idle and costs nothing). St: a Stencil, or
// a StoredStencil read in place.
template <class St>
void velocity_gradient_gather(const St& st, const GradientWindow& win, double (&L)[3][4]) {
  constexpr int W = St::W;
  const double(&v)[3][GradientWindow::kSize] = win.v;
  Lanes<4> A[W], B[W], C[W];
  for (int a = 0; a < W; ++a) {
    A[a] = Lanes<4>::set(st.dw[0][a], st.w[0][a], st.w[0][a], st.w[0][a]);
    B[a] = Lanes<4>::set(st.w[1][a], st.dw[1][a], st.w[1][a], st.w[1][a]);
    C[a] = Lanes<4>::set(st.w[2][a], st.w[2][a], st.dw[2][a], st.w[2][a]);
  }
  Lanes<4> L0 = Lanes<4>::zero(), L1 = Lanes<4>::zero(), L2 = Lanes<4>::zero();
  for (int a = 0; a < W; ++a) {
    for (int b = 0; b < W; ++b) {
      const Lanes<4> ab = A[a] * B[b];
      const int row = GradientWindow::row(st, a, b);
      for (int c = 0; c < W; ++c) {
        const int i = row + c;
        const Lanes<4> g = ab * C[c];
        L0 = fma(Lanes<4>::splat(v[0][i]), g, L0);
        L1 = fma(Lanes<4>::splat(v[1][i]), g, L1);
        L2 = fma(Lanes<4>::splat(v[2][i]), g, L2);
      }
    }
  }
  L0.store(L[0]);
  L1.store(L[1]);
  L2.store(L[2]);
}

// Grid velocity in p*: after the MUSL remap (FLIP), or straight from the grid update (APIC).
// Particles of one owner block that share one neighbour list; the window is the caller's scratch.
// kAxisymmetric: (r, z) = (x, z), the hoop direction y, whose stencil is degenerate (L_yj = 0,
// L_iy = 0: no torsion); the hoop strain rate L_yy = v_r / r_p = sum_I N_I v_rI / r_p (Sulsky &
// Schreyer 1996, CMAME 139; NairnMPM MatPointAS::UpdateStrain, dv(2,2) = sum v_x N_I / r_p),
// which the constitutive update of any material then sees as the y stretch. Near the axis the
// field v_r is odd in r (the symmetry face folds the ghost nodes), so sum N v_r -> 0 with r_p
// and the ratio stays finite.
template <class Shape, bool kAxisymmetric = false>
void velocity_gradient_block(const GradientParticles& in, std::span<const std::uint32_t> particles,
                             const SparseGrid::Coord& owner, const std::uint32_t* neighbours,
                             const SparseGrid::Nodes& nodes, GradientWindow& win) {
  const double* fields[3] = {nodes.px.data(), nodes.py.data(), nodes.pz.data()};
  win.load(neighbours, fields, 3);
  Stencil<Shape> st;
  const bool stored = in.stencil.mode == StencilCache::kLoad;
  // The particle's increments from its gathered L.
  const auto update = [&](std::uint32_t p, double(&L)[3][4]) {
    if constexpr (kAxisymmetric) L[1][1] = L[0][3] / (in.x[p] * in.inv_h);  // cell units
    if (in.vgrad[0] != nullptr) {
      for (int r = 0; r < 3; ++r) {
        for (int q = 0; q < 3; ++q) in.vgrad[3 * r + q][p] = in.inv_h * L[r][q];
      }
    }
    const double k = in.dt * in.inv_h;
    const std::size_t q = p - in.inc_begin;
    in.exx[q] = k * L[0][0];
    in.eyy[q] = k * L[1][1];
    in.ezz[q] = k * L[2][2];
    in.exy[q] = 0.5 * k * (L[0][1] + L[1][0]);
    in.eyz[q] = 0.5 * k * (L[1][2] + L[2][1]);
    in.exz[q] = 0.5 * k * (L[0][2] + L[2][0]);
    in.wxy[q] = 0.5 * k * (L[0][1] - L[1][0]);
    in.wyz[q] = 0.5 * k * (L[1][2] - L[2][1]);
    in.wxz[q] = 0.5 * k * (L[0][2] - L[2][0]);
    in.rho[p] /= 1.0 + k * (L[0][0] + L[1][1] + L[2][2]);  // App. A.2 step 7
  };
  if constexpr (kRecomputedRows<Shape>) {
    if (in.stencil.mode == StencilCache::kRecompute) {  // the engine's uGIMP case
      for_each_recomputed<Shape>(in.stencil, particles, [&](const auto& stencil, std::uint32_t p) {
        alignas(32) double L[3][4];
        velocity_gradient_gather(stencil, win, L);
        update(p, L);
      });
      return;
    }
  }
  for (const std::uint32_t p : particles) {
    alignas(32) double L[3][4];
    if (stored) {  // read in place (StoredStencil)
      velocity_gradient_gather(StoredStencil<Shape>(in.stencil, p), win, L);
    } else {
      const double x[3] = {in.x[p], in.y[p], in.z[p]};
      st.prepare(in.stencil, p, x, in.inv_h, 0.5 * in.size0[p] * in.inv_h, owner);
      velocity_gradient_gather(st, win, L);
    }
    update(p, L);
  }
}

}  // namespace shatter::kernels
