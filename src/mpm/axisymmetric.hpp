#pragma once
// The axisymmetric (r-z) geometry of the MPM engine (SolverConfig::Geometry): what the engine
// requires of a configuration and of the particles before it runs in r-z.

#include "shatter/core/config.hpp"
#include "shatter/core/particles.hpp"

namespace shatter::mpm {

// Throws std::invalid_argument, naming the scene key, when an axisymmetric run is asked for with
// something the r-z engine does not carry (docs/validation-axisymmetric.md): the uGIMP shape,
// a transfer other than FLIP, multi-field contact, self-gravity, gravity off the z axis, several
// MPI ranks, an axis that is not a symmetry face at x = 0, or a point off the y = 0 half-plane
// x > 0 or with a velocity off the (r, z) plane. Does nothing in 3-D.
void check_axisymmetric(const SolverConfig& c, const ParticleStore& P, bool several_ranks);

}  // namespace shatter::mpm
