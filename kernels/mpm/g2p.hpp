#pragma once
// Grid-to-particle update (App. A.2 step 5): particle velocity from the nodal accelerations
// F_I / M_I and particle displacement from the nodal velocities P_I^{n+1/2} / M_I. The
// displacement is kept aside: steps 6-7 still need the shape functions at x^n.

#include <cstdint>

#include "mpm/stencil.hpp"

namespace shatter::kernels {

struct G2PParticles {
  const double *x, *y, *z, *size0;
  double *vx, *vy, *vz;
  double *dx, *dy, *dz;  // out: displacement over the step
  double inv_h;
  double dt_velocity;  // dt^n = (dt^{n-1/2} + dt^{n+1/2}) / 2 (leapfrog, Fig. 16)
  double dt_position;  // dt^{n+1/2}
  bool pic;            // APIC: the particle takes the grid velocity instead of adding a dt (FLIP)
};

// Grid arrays after the grid update: acceleration in f*, velocity in p*.
template <class Shape>
void g2p_particle(const G2PParticles& in, std::size_t p, const SparseGrid::Coord& owner,
                  const std::uint32_t* neighbours, const SparseGrid::Nodes& nodes) {
  constexpr int W = Shape::kWidth;
  Stencil<Shape> st;
  const double xi[3] = {in.x[p] * in.inv_h, in.y[p] * in.inv_h, in.z[p] * in.inv_h};
  st.compute(xi, 0.5 * in.size0[p] * in.inv_h, owner);
  double ax = 0, ay = 0, az = 0, ux = 0, uy = 0, uz = 0;
  for (int a = 0; a < W; ++a) {
    for (int b = 0; b < W; ++b) {
      const double wab = st.w[0][a] * st.w[1][b];
      for (int c = 0; c < W; ++c) {
        const std::uint32_t i = st.node(neighbours, a, b, c);
        const double N = wab * st.w[2][c];
        ax += N * nodes.fx[i];
        ay += N * nodes.fy[i];
        az += N * nodes.fz[i];
        ux += N * nodes.px[i];
        uy += N * nodes.py[i];
        uz += N * nodes.pz[i];
      }
    }
  }
  if (in.pic) {
    in.vx[p] = ux;
    in.vy[p] = uy;
    in.vz[p] = uz;
  } else {
    in.vx[p] += in.dt_velocity * ax;
    in.vy[p] += in.dt_velocity * ay;
    in.vz[p] += in.dt_velocity * az;
  }
  in.dx[p] = in.dt_position * ux;
  in.dy[p] = in.dt_position * uy;
  in.dz[p] = in.dt_position * uz;
}

}  // namespace shatter::kernels
