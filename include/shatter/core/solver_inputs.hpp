#pragma once
// Checks both methods make on the particles and materials they are given, before any set-up
// (MPM's Simulation and SPH's SphSolver), so that the two refuse bad input with the same words.

#include <initializer_list>
#include <vector>

#include "shatter/core/particles.hpp"
#include "shatter/material/material_model.hpp"

namespace shatter {

// Throws std::invalid_argument, naming what is wrong, when a field of `required` is missing, the
// store is empty, a group names a material that is not in `materials`, or a particle has a mass
// or density that is not finite and positive.
void check_solver_inputs(const ParticleStore& particles, const std::vector<MaterialPtr>& materials,
                         std::initializer_list<Field> required);

}  // namespace shatter
