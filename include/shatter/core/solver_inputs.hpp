#pragma once
// Checks both methods make on the particles and materials they are given, before any set-up
// (MPM's Simulation and SPH's SphSolver), so that the two refuse bad input with the same words.

#include <initializer_list>
#include <string_view>
#include <vector>

#include "shatter/core/particles.hpp"
#include "shatter/core/solver.hpp"
#include "shatter/material/material_model.hpp"

namespace shatter {

// Throws std::invalid_argument, naming what is wrong, when a field of `required` is missing, the
// store is empty, a group names a material that is not in `materials`, or a particle has a mass
// or density that is not finite and positive.
void check_solver_inputs(const ParticleStore& particles, const std::vector<MaterialPtr>& materials,
                         std::initializer_list<Field> required);

// Throws NumericalError when the step just chosen (clk.dt) is not finite (`why_not_finite` says
// which limits were missing) or fell below dt_min, with the step and the time.
void check_new_time_step(const Clock& clk, double dt_min, std::string_view why_not_finite);

}  // namespace shatter
