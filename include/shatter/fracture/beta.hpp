#pragma once
// The momentum enhancement of a kinetic impact (issue 32), measured from the particles:
//
//   beta = 1 + p_ej / p_imp                        (Cheng et al. 2023, Nature 616, Eq. 1;
//                                                    Raducan et al. 2019, Icarus 329, Sec. 2)
//
// along the impact direction d (the impactor's velocity, unit): p_imp = m_imp U, the impactor's
// momentum before the impact (its points' mass times the scene's impact speed U), and p_ej the
// momentum the ejecta carry back out, p_ej = sum_ejecta m_p v_p . (-d).
//
// Which points are ejecta (docs/validation-dart.md says why): a point is ejecta while it is
// above the control plane, the pre-impact target surface {x : (x - x_s) . n = 0} with outward
// normal n, and moving outward, v . n > 0; and, when the scene gives an escape speed, only while
// |v| >= v_esc (Raducan et al. 2019; Stickle et al. 2022, PSJ 3, count the ejecta that leave the
// target's gravity). The test is on the present state only, so beta(t) is a function of the
// snapshot: it needs no memory, restarts exactly, and is the same on any rank count (exact sums).
//
// By momentum conservation the material left below the plane (the target and the buried
// impactor) carries beta p_imp along d: `beta_target` measures that, and differs from `beta` by
// the momentum the domain's boundaries took (fixed or outflow faces) or the integrator lost.

#include <array>
#include <cstdint>

#include <Eigen/Core>

#include "shatter/core/particles.hpp"
#include "shatter/parallel/exact_sum.hpp"

namespace shatter {

// [beta] of a scene (src/scene/parse_beta.cpp).
struct BetaSpec {
  std::int64_t impactor = -1;                               // body id of the impactor
  Eigen::Vector3d direction = -Eigen::Vector3d::UnitZ();    // d, unit: the impactor's velocity
  double impact_speed = 0.0;                                // U = v_imp . d, m/s (> 0)
  Eigen::Vector3d surface_point = Eigen::Vector3d::Zero();  // x_s, on the control plane
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();        // n, unit, out of the target
  double escape_speed = 0.0;  // m/s; 0: every outward point above the plane counts
};

// The exact sums beta is formed from (summed over the ranks first when distributed):
// [0] ejecta mass, [1] ejecta momentum along -d, [2] impactor mass, [3] momentum along d of the
// points that are not ejecta.
using BetaSums = std::array<parallel::ExactSum, 4>;

struct BetaSample {
  double ejecta_mass = 0.0;        // kg
  double ejecta_momentum = 0.0;    // kg m/s, along -d
  double impactor_momentum = 0.0;  // kg m/s, m_imp U
  double beta = 1.0;               // 1 + p_ej / p_imp
  double beta_target = 0.0;        // (momentum along d of what is not ejecta) / p_imp
};

// Whether a point at x with velocity v is ejecta under `spec` (the test above).
bool is_ejecta(const BetaSpec& spec, const Eigen::Vector3d& x, const Eigen::Vector3d& v);

BetaSums beta_sums(const ParticleStore& store, const BetaSpec& spec);
// beta from the sums with the impactor's mass before the impact, m_imp (kg: the run's first
// sample; impactor points that later leave through an outflow face must not change p_imp);
// beta = 1 and beta_target = 0 when m_imp is 0.
BetaSample beta_sample(BetaSums& sums, const BetaSpec& spec, double impactor_mass);
// From the present points alone (m_imp = the impactor points' mass now).
BetaSample measure_beta(const ParticleStore& store, const BetaSpec& spec);

}  // namespace shatter
