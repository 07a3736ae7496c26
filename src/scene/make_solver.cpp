#include <fmt/format.h>

#include "mpm/driven.hpp"
#include "shatter/mpm/simulation.hpp"
#include "shatter/scene/build.hpp"
#include "shatter/sph/solver.hpp"

namespace shatter::scene {

std::unique_ptr<Solver> make_solver(const Scene& scene, ParticleStore particles,
                                    std::vector<MaterialPtr> materials, int threads) {
  // Driven bodies (body.NAME.driven): ids are the order of scene.bodies (build.cpp).
  std::vector<std::int32_t> driven;
  for (std::size_t g = 0; g < scene.bodies.size(); ++g) {
    if (scene.bodies[g].driven) driven.push_back(static_cast<std::int32_t>(g));
  }
  if (!driven.empty() && driven.size() == scene.bodies.size()) {
    throw SceneError(scene.bodies.front().where, "body." + scene.bodies.front().name + ".driven",
                     "every body is driven: nothing is left free to move");
  }
  if (scene.method == "sph") {
    auto sph = std::make_unique<sph::SphSolver>(scene.solver, scene.sph, std::move(particles),
                                                std::move(materials), threads);
    if (!driven.empty()) {
      // The same law as MPM's: each driven point keeps the velocity it has now, re-imposed after
      // every kick (BA95's grips, Sec. 5.1).
      auto held = std::make_shared<mpm::DrivenBodies>(sph->particles(), driven);
      sph->set_velocity_constraint([held](double, ParticleStore& P) { held->hold(P); });
    }
    return sph;
  }
  if (scene.method == "mpm") {
    auto sim = std::make_unique<Simulation>(scene.solver, std::move(particles),
                                            std::move(materials), threads);
    sim->set_driven(driven);
    return sim;
  }
  throw std::invalid_argument(
      fmt::format("solver.method: unknown method '{}' (mpm or sph)", scene.method));
}

}  // namespace shatter::scene
