#pragma once
// Flaw initialisation for Grady–Kipp damage (ISSUE fracture): per particle eps_min, eps_max,
// number of flaws and local Weibull exponent. Implemented in src/fracture/flaws.cpp.

#include <cstdint>
#include <map>
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
  // r-z (issue 31): each point is a ring about z, volume0 = 2 pi x A. A ring then holds the flaws
  // of one 3-D point of its cross-section's size (volume A^(3/2)), not of its whole volume, so
  // that its damage is that of a 3-D point at the same spacing (resolution_independent only).
  bool rings = false;
};

// Fills eps_min, eps_max, n_flaws, weibull_m (and zeroes n_active) for the particles of `range`
// (one body; V of Eqs. 15–20 is the sum of their volume0 and n_p their number, both times
// `copies`: a body cut by a symmetry plane is simulated as one half, copies = 2, yet its flaws
// are those of the whole body — with the half's V every threshold would be 2^(1/m) too high and
// n_f doubled). Random numbers come from a
// counter-based stream keyed by (seed, particle id) — for benz_asphaug by (seed, flaw index),
// which picks a particle by its rank among the sorted ids — so the result does not depend on
// thread count or particle order. Requires IField::id and Field::volume0; registers the flaw
// columns. Throws std::invalid_argument on an unknown scheme or non-physical parameters
// (m <= 0, k <= 0, or n_tot <= 10^m for resolution_independent, which the paper requires).
void initialise_flaws(ParticleStore& store, Range range, const FlawSpec& spec,
                      std::size_t copies = 1);

// Flaw statistics of one body, to check against MPM paper Eq. 16.
struct FlawStatistics {
  std::size_t particles = 0;           // stored particles (of the half, for a half model)
  double volume = 0.0;                 // V = copies x sum of volume0 [m^3]: the whole body
  double total_flaws = 0.0;            // copies x sum of n_f over particles: the whole body
  double mean_flaws = 0.0;             // mean n_f per particle
  double mean_local_m = 0.0;           // mean m_p over particles with n_f > 1
  double eps_min_volume = 0.0;         // eps_min,V = (k V)^(-1/m)
  double mean_eps_min = 0.0;           // mean over particles of eps_min,p ("active strain")
  double expected_mean_eps_min = 0.0;  // 10 m / (m + 1) eps_min,V (resolution_independent)
  // Flaw-weighted mean threshold under each particle's local Weibull law (Eq. 17):
  // per particle m_p/(m_p+1) eps_max + eps_min / (n_f (m_p+1)).
  double mean_activation_strain = 0.0;
  // Eq. 16 with n_tot = total_flaws: m/(m+1) (n_tot / (k V))^(1/m).
  double eq16_activation_strain = 0.0;
};

// `copies` as for initialise_flaws: the statistics are those of the whole body.
FlawStatistics flaw_statistics(const ParticleStore& store, Range range, const FlawSpec& spec,
                               std::size_t copies = 1);

// Reads the flaw keys of a grady_kipp DamageSpec's params (see src/materials/damage_factory.hpp):
// weibull_m, weibull_k, total_flaws, explicit_flaws (1 = benz_asphaug), seed. Keys it does not
// know are ignored here (materials::make_damage_policy validates the full set).
FlawSpec flaw_spec_from_params(const std::map<std::string, double>& params, double young);

}  // namespace shatter
