#pragma once
// What every equation of state returns, and the guards they share (MPM paper Sec. 3.2).

#include "constitutive/simd.hpp"

namespace shatter::eos {

// Pressure and squared bulk sound speed c_K^2 (Eq. 12) at one (rho, E) state.
template <class T>
struct EosPoint {
  T p;
  T c2;
};

// Eq. 12: c_K^2 = dp/drho|_E + p / rho^2 * dp/dE|_rho, with the derivatives of the branch in use.
template <class T>
inline T isentropic_c2(const T& rho, const T& p, const T& dp_drho, const T& dp_de) {
  return dp_drho + p / (rho * rho) * dp_de;
}

// Expanded and tensile states can make Eq. 12 negative (the EOS is not convex there). The time
// step, the artificial viscosity and the crack speed (c_g = 0.4 c_p, Eq. 19) all need a real
// positive speed, so each EOS floors c_K^2 at a small fraction of its reference value:
// c_K >= kSoundFloor * c_0. One per cent keeps the floor far below any physical wave speed of a
// condensed state and thus never changes the time step of a run that is not in vapour.
inline constexpr double kSoundFloor = 1e-2;

// Densities are clamped from below before evaluating an EOS, so that rho -> 0 (a point that
// flew apart) gives finite p and c instead of 0/0: below 1e-12 rho0 every EOS here is already in
// its asymptotic vapour branch, so the clamp changes no value a run can distinguish.
inline constexpr double kMinDensityFraction = 1e-12;

}  // namespace shatter::eos
