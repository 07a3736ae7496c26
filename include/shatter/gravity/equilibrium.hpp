#pragma once
// The lithostatic start (issue 30): each body set in hydrostatic equilibrium under its own
// gravity before the run, as Benz & Asphaug 1999 and Jutzi et al. 2010 start their targets, so
// that a large target neither rings nor collapses before it is hit. Implemented in
// src/gravity/equilibrium.cpp.

#include <vector>

#include "shatter/core/particles.hpp"
#include "shatter/material/material_model.hpp"
#include "shatter/material/rest_compaction.hpp"

namespace shatter::gravity {

// Per body (IField::body b, material group b: the scene's layout): the body is taken as a
// uniform sphere of its own mass M and volume V (sum of volume0) about its centre of mass, of
// radius R = (3 V / 4 pi)^(1/3), with the hydrostatic pressure of a uniform self-gravitating
// sphere (e.g. Turcotte & Schubert 2002, Eq. 2-71 for an incompressible planet)
//   p(r) = 2/3 pi G rho^2 (R^2 - r^2),   p(0) = 3 G M^2 / (8 pi R^4),
// zero outside R. Each point's density is raised until its material's EOS (the model's own
// initialise) gives p(r) (secant steps from rho c^2), and its stress is set to -p I. Mass and
// positions are kept: the compression of a rock body is p / K ~ 1e-5 at 25 km.
// A porous body (its entry of `rest`, its material's rest_compaction, given, with alpha0 > 1;
// issue 29) starts instead on its crush curve, as set_uniform_equilibrium's column below: the
// sphere of the same radius and centre in hydrostatic balance with a bulk density that grows inward
// as the pores close, dp/dr = -G m(r) rho(p) / r^2, dm/dr = 4 pi r^2 rho(p), p(R) = 0, rho(p) the
// density at which the compaction model at rest carries p (integrated outward by RK4 and shot on
// the central pressure); each point at its radius's pressure, at that density and at the
// distension the compaction model gives there; its volume (volume0) and position kept and its
// mass set to rho volume0, so the body weighs more than its rest density says
// (docs/validation-qstar.md, "The equilibrium start").
// Returns the largest relative pressure residual |p_eos - p| / p(0) left.
double set_equilibrium(ParticleStore& store, const std::vector<MaterialPtr>& materials, double G,
                       const std::vector<RestCompactionFn>& rest = {});

// The lithostatic start under a uniform field g = (0, 0, -g_z), g_z > 0 (issue 29, gravity-regime
// craters): each body that rests on the domain's lower z face (its lowest point within one cell
// of z_lo; the caller passes z_lo only when that face is fixed or slip, so the weight is borne)
// gets the overburden pressure of a uniform column,
//   p(z) = rho_b g_z (z_top - z)   (e.g. Turcotte & Schubert 2002, Eq. 2-1, p = rho g y),
// rho_b = M / V of the body (sum of mass over sum of volume0: the mass per area above a point
// does not change when the column is compressed, so this is the weight of the overburden
// exactly), z_top the body's highest point plus half its point spacing (its free surface).
// Density and stress as set_equilibrium: the density raised until the model's initialise gives
// p(z), stress -p I. A porous body (one whose entry of `rest`, its material's rest_compaction, is
// given, with alpha0 > 1; issue 29) starts instead on its crush curve: p(z) = g_z times the mass
// per area above z of a column whose bulk density grows with depth as the pores close (dp/dd = g_z
// rho(p), integrated from the free surface), each point at the density that carries p(z) at rest
// and at the distension the compaction model gives there (rest_compaction.hpp: P-alpha's alpha(P),
// eps-alpha's alpha(eps_V)); its volume (volume0) is kept and its mass set to rho volume0, so the
// body weighs more than its rest density says (docs/validation-porosity.md, "Session 20"). With an
// overburden below the crush curve's elastic limit the distension stays alpha0 and only the
// density's elastic compression (p / K) enters the mass.
// Bodies off the lower face (a projectile in free fall) are left as they are: free fall is
// stress-free. Returns the largest relative residual |p_eos - p| / p_max of the settled bodies.
double set_uniform_equilibrium(ParticleStore& store, const std::vector<MaterialPtr>& materials,
                               double g_z, double z_lo, double cell,
                               const std::vector<RestCompactionFn>& rest = {});

// The lithostatic pressure rho g depth, for the checks.
double lithostatic_pressure(double rho, double g_z, double depth);

// The hydrostatic pressure above, for the checks.
double hydrostatic_pressure(double G, double rho, double R, double r);

}  // namespace shatter::gravity
