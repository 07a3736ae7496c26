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

// The hydrostatic pressure above, for the checks.
double hydrostatic_pressure(double G, double rho, double R, double r);

}  // namespace shatter::gravity
