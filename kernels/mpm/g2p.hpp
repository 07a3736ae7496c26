#pragma once
// Grid-to-particle update (App. A.2 step 5): particle velocity from the nodal accelerations
// F_I / M_I (FLIP) and/or a filtered grid velocity (PIC, XPIC, APIC; see TransferKind), and
// particle displacement from the nodal velocities P_I^{n+1/2} / M_I. The displacement is kept
// aside: steps 6-7 still need the shape functions at x^n.

#include <cstdint>
#include <span>

#include "mpm/lanes.hpp"
#include "mpm/stencil.hpp"

namespace shatter::kernels {

struct G2PParticles {
  const double *x, *y, *z, *size0;
  double *vx, *vy, *vz;
  double *dx, *dy, *dz;  // out: displacement over the step
  double inv_h;
  double dt_velocity;  // dt^n = (dt^{n-1/2} + dt^{n+1/2}) / 2 (leapfrog, Fig. 16)
  double dt_position;  // dt^{n+1/2}
  // Share of the filtered grid velocity w = S v_f in the new particle velocity:
  // v_p <- (1 - f) (v_p + S a dt) + f w. 0: FLIP (the paper's step 5); 1: the particle takes the
  // grid velocity (APIC, PIC, XPIC); in between: the FLIP/PIC blend. 0 and 1 are exact branches,
  // so FLIP and PIC are bitwise what they were.
  double pic_fraction;
  // Nodal velocity v_f that w interpolates; null: the updated grid velocity v^{n+1} (in p*).
  // XPIC's S (V*_m + a dt) (Hammerquist & Nairn 2017) comes in here.
  const double *fvx, *fvy, *fvz;
  // Out, when not null: the plain FLIP velocity v_p + S a dt of the same step, whatever the
  // update (the filter-heat booking of SolverConfig::filter_heat compares the two).
  double *flip_vx = nullptr, *flip_vy = nullptr, *flip_vz = nullptr;
  StencilCache stencil;  // kLoad: the stencils P2G stored this step
};

// Interpolated nodal velocity at a particle, w_p = sum_I N_I(x_p) v_I: the S operator of
// Hammerquist & Nairn (2017), used by XPIC's extra grid-particle-grid passes.
// St: a Stencil, or a StoredStencil read in place (stencil.hpp).
template <class St>
void gather_velocity_at(const St& st, const std::uint32_t* neighbours, const double* vx,
                        const double* vy, const double* vz, double& wx, double& wy, double& wz) {
  constexpr int W = St::W;
  double ux = 0, uy = 0, uz = 0;
  for (int a = 0; a < W; ++a) {
    for (int b = 0; b < W; ++b) {
      const double wab = st.w[0][a] * st.w[1][b];
      for (int c = 0; c < W; ++c) {
        const std::uint32_t i = node_index(st, neighbours, a, b, c);
        const double N = wab * st.w[2][c];
        ux += N * vx[i];
        uy += N * vy[i];
        uz += N * vz[i];
      }
    }
  }
  wx = ux;
  wy = uy;
  wz = uz;
}

template <class Shape>
void gather_velocity(const G2PParticles& in, std::size_t p, const SparseGrid::Coord& owner,
                     const std::uint32_t* neighbours, const double* vx, const double* vy,
                     const double* vz, double* wx, double* wy, double* wz) {
  if (in.stencil.mode == StencilCache::kLoad) {  // the engine's case: the row in place
    gather_velocity_at(StoredStencil<Shape>(in.stencil, p), neighbours, vx, vy, vz, wx[p], wy[p],
                       wz[p]);
    return;
  }
  Stencil<Shape> st;
  const double x[3] = {in.x[p], in.y[p], in.z[p]};
  st.prepare(in.stencil, p, x, in.inv_h, 0.5 * in.size0[p] * in.inv_h, owner);
  gather_velocity_at(st, neighbours, vx, vy, vz, wx[p], wy[p], wz[p]);
}

// The node fields of a G2P window, side by side per node so that one vector load takes a node's
// values (lanes.hpp): acceleration f* and velocity p* in `fp` (lanes 0-2 and 3-5, two zero
// lanes), XPIC's filtered velocity in `fv` (lanes 0-2, one zero lane) when there is one.
struct G2PWindow : WindowGeometry {
  double fp_[kSize * 8 + 7], fv_[kSize * 4 + 7];  // see fp() and fv()
  double* fp(int i) { return align64(fp_) + 8 * i; }
  double* fv(int i) { return align64(fv_) + 4 * i; }
  const double* fp(int i) const { return align64(fp_) + 8 * i; }
  const double* fv(int i) const { return align64(fv_) + 4 * i; }

  // fields: f*, p* (x, y, z each), then the filtered velocity, read only when `filtered`.
  void load(const std::uint32_t* neighbours, const double* const (&fields)[9], bool filtered) {
    visit(neighbours, [&](int i, std::size_t g) {
      double* n = fp(i);
      for (int f = 0; f < 6; ++f) n[f] = fields[f][g];
      n[6] = n[7] = 0.0;
    });
    if (filtered) {
      visit(neighbours, [&](int i, std::size_t g) {
        double* n = fv(i);
        for (int f = 0; f < 3; ++f) n[f] = fields[6 + f][g];
        n[3] = 0.0;
      });
    }
  }
};

// sum_I N_I(x_p) u_I over the stencil of `st` for the window fields of G2PWindow: lanes 0-5 of
// `fp` the acceleration and velocity, `fv` the filtered velocity (Filtered only). The weights are
// N = (w_x w_y) w_z as in the scalar loop, and each lane adds fma(N, u_I, sum) node by node.
// St: a Stencil, or a StoredStencil read in place.
template <bool Filtered, class St>
void g2p_gather(const St& st, const G2PWindow& win, double (&fp)[8], double (&fv)[4]) {
  constexpr int W = St::W;
  Lanes<8> s8 = Lanes<8>::zero();
  Lanes<4> s4 = Lanes<4>::zero();
  for (int a = 0; a < W; ++a) {
    for (int b = 0; b < W; ++b) {
      const double wab = st.w[0][a] * st.w[1][b];
      const int row = G2PWindow::row(st, a, b);
      for (int c = 0; c < W; ++c) {
        const int i = row + c;
        const double N = wab * st.w[2][c];
        s8 = fma(Lanes<8>::splat(N), Lanes<8>::load(win.fp(i)), s8);
        if constexpr (Filtered) s4 = fma(Lanes<4>::splat(N), Lanes<4>::load(win.fv(i)), s4);
      }
    }
  }
  s8.store(fp);
  if constexpr (Filtered) s4.store(fv);
}

// Grid arrays after the grid update: acceleration in f*, velocity in p*. Particles of one owner
// block that share one neighbour list (all of them, except where bodies meet); the window is
// the caller's scratch. after(p, v0) runs once per particle with its velocity before the update.
template <class Shape, class After>
void g2p_block(const G2PParticles& in, std::span<const std::uint32_t> particles,
               const SparseGrid::Coord& owner, const std::uint32_t* neighbours,
               const SparseGrid::Nodes& nodes, G2PWindow& win, After&& after) {
  const bool filtered = in.fvx != nullptr;
  const double* const fields[9] = {nodes.fx.data(), nodes.fy.data(), nodes.fz.data(),
                                   nodes.px.data(), nodes.py.data(), nodes.pz.data(),
                                   in.fvx,          in.fvy,          in.fvz};
  win.load(neighbours, fields, filtered);
  Stencil<Shape> st;
  const bool stored = in.stencil.mode == StencilCache::kLoad;
  const auto gather = [&](const auto& stencil, double(&s)[8], double(&t)[4]) {
    if (filtered) {
      g2p_gather<true>(stencil, win, s, t);
    } else {
      g2p_gather<false>(stencil, win, s, t);
    }
  };
  // The particle's update from its gathered sums s (acceleration, velocity) and t (filtered).
  const auto update = [&](std::uint32_t p, const double(&s)[8], const double(&t)[4]) {
    const double ax = s[0], ay = s[1], az = s[2], ux = s[3], uy = s[4], uz = s[5];
    const double wx = filtered ? t[0] : ux, wy = filtered ? t[1] : uy, wz = filtered ? t[2] : uz;
    const double v0[3] = {in.vx[p], in.vy[p], in.vz[p]};
    const double f = in.pic_fraction;
    if (in.flip_vx != nullptr) {
      in.flip_vx[p] = v0[0] + in.dt_velocity * ax;
      in.flip_vy[p] = v0[1] + in.dt_velocity * ay;
      in.flip_vz[p] = v0[2] + in.dt_velocity * az;
    }
    if (f == 1.0) {
      in.vx[p] = wx;
      in.vy[p] = wy;
      in.vz[p] = wz;
    } else if (f == 0.0) {
      in.vx[p] += in.dt_velocity * ax;
      in.vy[p] += in.dt_velocity * ay;
      in.vz[p] += in.dt_velocity * az;
    } else {
      const double g = 1.0 - f;
      in.vx[p] = g * (in.vx[p] + in.dt_velocity * ax) + f * wx;
      in.vy[p] = g * (in.vy[p] + in.dt_velocity * ay) + f * wy;
      in.vz[p] = g * (in.vz[p] + in.dt_velocity * az) + f * wz;
    }
    in.dx[p] = in.dt_position * ux;
    in.dy[p] = in.dt_position * uy;
    in.dz[p] = in.dt_position * uz;
    after(p, v0);
  };
  if constexpr (kRecomputedRows<Shape>) {
    if (in.stencil.mode == StencilCache::kRecompute) {  // the engine's uGIMP case
      for_each_recomputed<Shape, false>(in.stencil, particles,
                                        [&](const auto& stencil, std::uint32_t p) {
                                          alignas(64) double s[8];
                                          alignas(32) double t[4] = {};
                                          gather(stencil, s, t);
                                          update(p, s, t);
                                        });
      return;
    }
  }
  for (const std::uint32_t p : particles) {
    alignas(64) double s[8];
    alignas(32) double t[4] = {};
    if (stored) {  // read in place (StoredStencil)
      gather(StoredStencil<Shape>(in.stencil, p), s, t);
    } else {
      const double x[3] = {in.x[p], in.y[p], in.z[p]};
      st.prepare(in.stencil, p, x, in.inv_h, 0.5 * in.size0[p] * in.inv_h, owner);
      gather(st, s, t);
    }
    update(p, s, t);
  }
}

}  // namespace shatter::kernels
