#include <fmt/format.h>

#include "shatter/mpm/simulation.hpp"
#include "shatter/scene/build.hpp"
#include "shatter/sph/solver.hpp"

namespace shatter::scene {

std::unique_ptr<Solver> make_solver(const Scene& scene, ParticleStore particles,
                                    std::vector<MaterialPtr> materials, int threads) {
  if (scene.method == "sph") {
    return std::make_unique<sph::SphSolver>(scene.solver, scene.sph, std::move(particles),
                                            std::move(materials), threads);
  }
  if (scene.method == "mpm") {
    return std::make_unique<Simulation>(scene.solver, std::move(particles), std::move(materials),
                                        threads);
  }
  throw std::invalid_argument(
      fmt::format("solver.method: unknown method '{}' (mpm or sph)", scene.method));
}

}  // namespace shatter::scene
