#pragma once
// The lithostatic start (issue 30): each body set in hydrostatic equilibrium under its own
// gravity before the run, as Benz & Asphaug 1999 and Jutzi et al. 2010 start their targets, so
// that a large target neither rings nor collapses before it is hit. Implemented in
// src/gravity/equilibrium.cpp.

#include <vector>

#include "shatter/core/particles.hpp"
#include "shatter/material/material_model.hpp"

namespace shatter::gravity {

// Per body (IField::body b, material group b: the scene's layout): the body is taken as a
// uniform sphere of its own mass M and volume V (sum of volume0) about its centre of mass, of
// radius R = (3 V / 4 pi)^(1/3), with the hydrostatic pressure of a uniform self-gravitating
// sphere (e.g. Turcotte & Schubert 2002, Eq. 2-71 for an incompressible planet)
//   p(r) = 2/3 pi G rho^2 (R^2 - r^2),   p(0) = 3 G M^2 / (8 pi R^4),
// zero outside R. Each point's density is raised until its material's EOS (the model's own
// initialise) gives p(r) (secant steps from rho c^2), and its stress is set to -p I. Mass and
// positions are kept: the compression of a rock body is p / K ~ 1e-5 at 25 km.
// Returns the largest relative pressure residual |p_eos - p| / p(0) left.
double set_equilibrium(ParticleStore& store, const std::vector<MaterialPtr>& materials, double G);

// The lithostatic start under a uniform field g = (0, 0, -g_z), g_z > 0 (issue 29, gravity-regime
// craters): each body that rests on the domain's lower z face (its lowest point within one cell
// of z_lo; the caller passes z_lo only when that face is fixed or slip, so the weight is borne)
// gets the overburden pressure of a uniform column,
//   p(z) = rho_b g_z (z_top - z)   (e.g. Turcotte & Schubert 2002, Eq. 2-1, p = rho g y),
// rho_b = M / V of the body (sum of mass over sum of volume0: the mass per area above a point
// does not change when the column is compressed, so this is the weight of the overburden
// exactly), z_top the body's highest point plus half its point spacing (its free surface).
// Density and stress as set_equilibrium: the density raised until the model's initialise gives
// p(z), stress -p I. A porous point keeps the distension it has (the material's alpha0): the
// state is consistent with the crush curve only while p stays in the model's elastic range
// (P-alpha: p < p_e; eps-alpha: strain above eps_e), which the scene has to provide (the
// column test, tests/unit/gravity/equilibrium_test.cpp, shows the column stays at rest).
// Bodies off the lower face (a projectile in free fall) are left as they are: free fall is
// stress-free. Returns the largest relative residual |p_eos - p| / p_max of the settled bodies.
double set_uniform_equilibrium(ParticleStore& store, const std::vector<MaterialPtr>& materials,
                               double g_z, double z_lo, double cell);

// The lithostatic pressure rho g depth, for the checks.
double lithostatic_pressure(double rho, double g_z, double depth);

// The hydrostatic pressure above, for the checks.
double hydrostatic_pressure(double G, double rho, double R, double r);

}  // namespace shatter::gravity
