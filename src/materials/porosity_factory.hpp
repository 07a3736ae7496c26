#pragma once
// MaterialSpec::porosity and its parameters -> the porosity policy of the composed kernel
// (kernels/porosity/porosity.hpp). Keys (SI units; schema.cpp lists them):
//   eps_alpha: alpha0 (>= 1), eps_e (<= 0), kappa (0 < kappa <= 1), eps_x (<= eps_e),
//              chi (0 < chi <= 1, default 1)
//   p_alpha:   alpha0 (>= 1), p_e (>= 0, Pa), p_s (> p_e, Pa), crush_exponent (> 0, default 2),
//              c_e (>= 0 m/s, default 0: the solid's sound speed throughout)
//   both:      deviator_scaling, compaction_damage (0 or 1; default 1 for p_alpha, JBM08; 0 for
//              eps_alpha): the porous bulk's strength and damage (kernels/porosity/porosity.hpp)

#include "porosity/porosity.hpp"
#include "shatter/material/catalogue.hpp"

namespace shatter::materials {

// Throws MaterialError naming the key of a parameter out of its range. No-op without porosity.
void check_porosity(const MaterialSpec& spec);

// Expects a validated spec with a porosity model.
porosity::Porous make_porosity(const MaterialSpec& spec);
// The crush curve alone (make_porosity without the strength and damage switches).
porosity::Porous make_crush(const MaterialSpec& spec);

}  // namespace shatter::materials
