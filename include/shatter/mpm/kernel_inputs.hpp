#pragma once
// The column pointers the transfer kernels read and write, taken from a ParticleStore in one
// place, so that the engine's stages and the stage benchmarks (bench/) run the kernels on the
// same inputs. Public (issue 28) so that bench/ needs no engine-internal header.

#include "mpm/g2p.hpp"
#include "mpm/p2g.hpp"
#include "mpm/velocity_gradient.hpp"
#include "shatter/core/particles.hpp"

namespace shatter::mpm {

// P2G (Eqs. 28-33). with_force: the stress columns too (the force-carrying scatter of step 1);
// without: mass and momentum only (the MUSL remap, step 6). Body forces and the APIC affine
// columns are the caller's to add.
inline kernels::P2GParticles p2g_inputs(ParticleStore& P, double inv_h, bool with_force) {
  kernels::P2GParticles in{};
  in.x = P.col(Field::x).data();
  in.y = P.col(Field::y).data();
  in.z = P.col(Field::z).data();
  in.vx = P.col(Field::vx).data();
  in.vy = P.col(Field::vy).data();
  in.vz = P.col(Field::vz).data();
  in.mass = P.col(Field::mass).data();
  in.rho = P.col(Field::rho).data();
  in.size0 = P.col(Field::size0).data();
  in.inv_h = inv_h;
  if (with_force) {
    in.sxx = P.col(Field::sxx).data();
    in.syy = P.col(Field::syy).data();
    in.szz = P.col(Field::szz).data();
    in.sxy = P.col(Field::sxy).data();
    in.syz = P.col(Field::syz).data();
    in.sxz = P.col(Field::sxz).data();
  }
  return in;
}

// G2P (step 5): particle velocities updated in place, displacement increments into dx/dy/dz.
// The two time steps and the transfer flag are the caller's.
inline kernels::G2PParticles g2p_inputs(ParticleStore& P, double inv_h, double* dx, double* dy,
                                        double* dz) {
  kernels::G2PParticles in{};
  in.x = P.col(Field::x).data();
  in.y = P.col(Field::y).data();
  in.z = P.col(Field::z).data();
  in.size0 = P.col(Field::size0).data();
  in.vx = P.col(Field::vx).data();
  in.vy = P.col(Field::vy).data();
  in.vz = P.col(Field::vz).data();
  in.dx = dx;
  in.dy = dy;
  in.dz = dz;
  in.inv_h = inv_h;
  return in;
}

// Velocity gradient (step 7): strain and spin increments and the density update, over dt.
inline kernels::GradientParticles gradient_inputs(ParticleStore& P, double inv_h, double dt) {
  kernels::GradientParticles in{};
  in.x = P.col(Field::x).data();
  in.y = P.col(Field::y).data();
  in.z = P.col(Field::z).data();
  in.size0 = P.col(Field::size0).data();
  in.rho = P.col(Field::rho).data();
  if (P.has(Field::deps_xx)) {  // else the caller points them at its chunk buffer
    in.exx = P.col(Field::deps_xx).data();
    in.eyy = P.col(Field::deps_yy).data();
    in.ezz = P.col(Field::deps_zz).data();
    in.exy = P.col(Field::deps_xy).data();
    in.eyz = P.col(Field::deps_yz).data();
    in.exz = P.col(Field::deps_xz).data();
    in.wxy = P.col(Field::dspin_xy).data();
    in.wyz = P.col(Field::dspin_yz).data();
    in.wxz = P.col(Field::dspin_xz).data();
  }
  in.inv_h = inv_h;
  in.dt = dt;
  return in;
}

}  // namespace shatter::mpm
