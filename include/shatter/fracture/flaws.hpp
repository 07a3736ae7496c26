#pragma once
// Flaw initialisation for Grady–Kipp damage (ISSUE fracture): per particle eps_min, eps_max,
// number of flaws and local Weibull exponent. Implemented in src/fracture/.

#include <cstdint>
#include <string>

#include "shatter/core/particles.hpp"

namespace shatter {

struct FlawSpec {
  // benz_asphaug: N ln N explicit flaws, eps_j = (j / (k V))^(1/m) (BA95 Eq. 20)
  // resolution_independent: the MPM paper's initialisation (Sec. 3.3, after Eq. 19)
  std::string scheme = "resolution_independent";
  double weibull_m = 8.5;
  double weibull_k = 3.0e39;   // m^-3
  double total_flaws = 1.0e9;  // n_tot (resolution-independent scheme)
  double young = 0.0;          // Young's modulus of the body, to turn stress into strain
  std::uint64_t seed = 1;
};

// Fills eps_min, eps_max, n_flaws, weibull_m for the particles of `range` (one body). Random
// numbers come from a counter-based stream keyed by (seed, particle id), so the result does not
// depend on thread count or particle order. Requires IField::id and Field::volume0.
void initialise_flaws(ParticleStore& store, Range range, const FlawSpec& spec);

}  // namespace shatter
