#pragma once
// MaterialSpec::porosity and its parameters -> the porosity policy of the composed kernel
// (kernels/porosity/porosity.hpp). Keys (SI units; schema.cpp lists them):
//   eps_alpha: alpha0 (>= 1), eps_e (<= 0), kappa (0 < kappa <= 1), eps_x (<= eps_e),
//              chi (0 < chi <= 1, default 1)
//   p_alpha:   alpha0 (>= 1), p_e (>= 0, Pa), p_s (> p_e, Pa), crush_exponent (> 0, default 2),
//              c_e (>= 0 m/s, default 0: the solid's sound speed throughout)

#include "porosity/porosity.hpp"
#include "shatter/material/catalogue.hpp"

namespace shatter::materials {

// Throws MaterialError naming the key of a parameter out of its range. No-op without porosity.
void check_porosity(const MaterialSpec& spec);

// Expects a validated spec with a porosity model.
porosity::Porous make_porosity(const MaterialSpec& spec);

}  // namespace shatter::materials
