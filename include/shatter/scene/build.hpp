#pragma once
// Turns a parsed scene into what the engine runs: the particle store (one material group per
// body) and the material models.

#include <vector>

#include "shatter/core/particles.hpp"
#include "shatter/material/material_model.hpp"
#include "shatter/scene/scene.hpp"

namespace shatter::scene {

struct BuiltScene {
  ParticleStore particles;
  std::vector<MaterialPtr> materials;  // materials[g] for group g (= body g)
  std::vector<bool> damaged;           // group g has a damage model (counts in the failure ratio)
};

// Models for each body, in body order (group g uses materials[g]).
std::vector<MaterialPtr> build_materials(const Scene& scene);

// Groups that carry a damage model.
std::vector<bool> damaged_groups(const Scene& scene);

// Creates the particles: positions from the lattice fill, velocity, rho = rho0, energy,
// volume0 = (measured body volume) / (number of points), mass = rho0 volume0, size0 = spacing,
// id (0..N-1 over all bodies), body index; flaws for Grady–Kipp bodies.
BuiltScene build(const Scene& scene);

}  // namespace shatter::scene
