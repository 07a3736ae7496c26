#pragma once
// Scene settings of the SPH method ([solver.sph]; see include/shatter/sph/solver.hpp).

namespace shatter::sph {

struct SphConfig {
  // h = h_factor (m / rho)^{1/3}: 1.2 gives 56 neighbours on a cubic lattice (support 2.4
  // spacings), near the ~50 of BA95 Sec. 4.2.
  double h_factor = 1.2;
  // Monaghan viscosity (kernels/sph/terms.hpp); Monaghan (1992) recommends alpha = 1, beta = 2.
  double alpha = 1.0;
  double beta = 2.0;
  // Verlet skin of the neighbour lists, as a fraction of the largest support 2 max h: the lists
  // hold pairs within h_i + h_j + skin and are reused until a particle has moved (plus grown
  // its h) by half the skin. Results do not depend on it (bitwise; tested), only the speed.
  // 0 = lists rebuilt every step.
  double skin = 0.1;
};

}  // namespace shatter::sph
