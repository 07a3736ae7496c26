#pragma once
// Turns a parsed scene into what the engine runs: the particle store (one material group per
// body) and the material models.

#include <memory>
#include <vector>

#include "shatter/core/particles.hpp"
#include "shatter/core/solver.hpp"
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

// The solver the scene's solver.method names: MPM's Simulation ("mpm") or the SPH solver
// ("sph"), on the given particles and materials. Throws std::invalid_argument for settings the
// method cannot take (e.g. a symmetry plane with SPH).
std::unique_ptr<Solver> make_solver(const Scene& scene, ParticleStore particles,
                                    std::vector<MaterialPtr> materials, int threads);

}  // namespace shatter::scene
