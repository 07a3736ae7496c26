#pragma once
// The compaction model of a porous material at rest (issue 29): the query the lithostatic start
// (src/gravity/equilibrium.cpp) asks to put a porous body on its crush curve under its own
// weight. Built, like the crush curve and the porous Hugoniot of probe.hpp, from the kernel's own
// porosity policy (kernels/porosity/porosity.hpp, materials::make_porosity) and the material's
// matrix EOS, so it answers what the composed model's step computes. Implemented in
// src/materials/crush_probe.cpp.

#include <functional>

#include "shatter/material/catalogue.hpp"

namespace shatter {

// A point of a porous material compressed monotonically from rest (bulk density rho_s0 / alpha0,
// distension alpha0) to bulk density rho at specific energy e: its distension on the compaction
// model's crush curve and its bulk pressure p_s(alpha rho, e) / alpha there.
struct RestCompaction {
  double alpha = 1.0;
  double pressure = 0.0;  // Pa
};
using RestCompactionFn = std::function<RestCompaction(double rho, double energy)>;

// The query of a porous material. P-alpha: the kernel's step from alpha0 (the root of alpha =
// crush(p_s(alpha rho, e) / alpha) below alpha0 does not depend on the path of a monotone
// loading). eps-alpha: the crush curve at eps_V = ln(rho00 / rho), a function of rho alone when
// chi = 1; with chi < 1 CMW11's reversible elastic regime (Eq. 6) makes alpha depend on the
// steps, and kRestSteps equal steps in ln rho stand for the monotone compression (the elastic
// range is |eps_e| ~ 1e-4 for sand: the choice moves alpha by < 1e-8 there). Throws
// std::invalid_argument for a material without porosity.
RestCompactionFn rest_compaction(const MaterialSpec& spec);
inline constexpr int kRestSteps = 64;

}  // namespace shatter
