#pragma once
// Scene settings of the SPH method ([solver.sph]; see include/shatter/sph/solver.hpp).

namespace shatter::sph {

// The SPH analogue of the continuity equation (kernels/sph/gather.hpp, rates_particle).
enum class Continuity {
  // BA95 Eq. 16 as printed: drho_i/dt = -sum_j m_j (v_j - v_i) . grad_i W_ij (the default).
  standard,
  // drho_i/dt = -rho_i sum_j (m_j / rho_j) (v_j - v_i) . grad_i W_ij, the same neighbour
  // weights V_j = m_j / rho_j in Eq. 18's velocity gradient (Randles & Libersky 1996). The
  // relative rate is then a divergence estimate that does not grow as rho_i falls below its
  // neighbours' density (docs/validation-sph.md, "The rho < 0 stop").
  normalized,
};

// Artificial viscosity coefficients (kernels/sph/terms.hpp).
enum class ViscositySwitch {
  none,             // alpha and beta constant (Monaghan 1992), the default
  morris_monaghan,  // alpha per particle, evolved as Morris & Monaghan (1997), beta = 2 alpha
};

struct SphConfig {
  // h = h_factor (m / rho)^{1/3}: 1.2 gives 56 neighbours on a cubic lattice (support 2.4
  // spacings), near the ~50 of BA95 Sec. 4.2.
  double h_factor = 1.2;
  // Monaghan viscosity (kernels/sph/terms.hpp); Monaghan (1992) recommends alpha = 1, beta = 2.
  // Not used with the Morris & Monaghan switch (alpha_min, alpha_max below; beta = 2 alpha).
  double alpha = 1.0;
  double beta = 2.0;
  // Verlet skin of the neighbour lists, as a fraction of the largest support 2 max h: the lists
  // hold pairs within h_i + h_j + skin and are reused until a particle has moved (plus grown
  // its h) by half the skin. Results do not depend on it (bitwise; tested), only the speed.
  // 0 = lists rebuilt every step.
  double skin = 0.1;
  Continuity continuity = Continuity::standard;
  // Morris & Monaghan (1997) switch: d alpha_i/dt = -(alpha_i - alpha_min) / tau_i
  // + max(-div v_i, 0) (alpha_max - alpha_i), tau_i = h_i / (switch_decay c_i). Every particle
  // starts at alpha_max. alpha_max = 1 keeps the viscosity at or below the constant default.
  ViscositySwitch viscosity_switch = ViscositySwitch::none;
  double alpha_min = 0.1;
  double alpha_max = 1.0;
  double switch_decay = 0.1;
};

}  // namespace shatter::sph
