// `shatter check SCENE`: the scene validated and its cost estimated (points per body, memory,
// first time step, steps, run time) without creating the particles; and the guard `shatter run`
// applies before allocating them. With --stages, the step's stage list as the scene builds it.

#include <thread>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "commands.hpp"
#include "progress.hpp"
#include "refused.hpp"
#include "resolution_advice.hpp"
#include "shatter/mpm/simulation.hpp"
#include "shatter/parallel/comm.hpp"
#include "shatter/scene/build.hpp"
#include "shatter/scene/estimate.hpp"

namespace shatter::cli {
namespace {

int threads_used(int requested) {
  if (requested > 0) return requested;
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

// What a stage does beyond its name, where the scene decides it: contact is resolved inside
// grid_update (src/mpm/stages/grid_update.cpp), so the list shows which contact runs there.
std::string stage_note(const std::string& name, const scene::Scene& s) {
  if (name == "grid_update") return fmt::format("  (contact: {})", name_of(s.solver.contact.kind));
  if (name == "p2g" || name == "g2p" || name == "xpic" || name == "fmpm") {
    return fmt::format("  (transfer: {})", name_of(s.solver.transfer));
  }
  if (name == "migrate" || name.starts_with("halo")) return "  (MPI exchange, src/parallel/mpm/)";
  return "";
}

// The particles are created (the solver's set-up needs them), so this costs what `run --check`
// costs. On several MPI ranks every rank builds the solver (a collective set-up), rank 0 prints.
int print_stages(const std::filesystem::path& scene_file, const RunOptions& options) {
  scene::Scene s;
  std::unique_ptr<Solver> sim;
  if (refused(scene_file, [&] {
        s = scene::load_scene(scene_file, options.sets);
        scene::BuiltScene built = scene::build(s);
        sim = scene::make_solver(s, std::move(built.particles), built.materials, options.threads);
      })) {
    return kBadInput;
  }
  const auto& world = parallel::world();
  if (world.rank() != 0) return kOk;
  if (const auto* mpm = dynamic_cast<const Simulation*>(sim.get())) {
    const std::vector<std::string> names = mpm->stage_names();
    fmt::print("stages: the MPM step (src/mpm/step.cpp) on {} rank{}, {} stages\n", world.size(),
               world.size() == 1 ? "" : "s", names.size());
    for (std::size_t i = 0; i < names.size(); ++i) {
      fmt::print("{:>3}. {}{}\n", i + 1, names[i], stage_note(names[i], s));
    }
    return kOk;
  }
  // SPH's step is fixed (src/sph/solver.cpp, SphSolver::step): its timed parts, in order.
  fmt::print("stages: the {} step is fixed (src/sph/solver.cpp), {} parts\n", sim->method(),
             sim->stage_timings().size());
  std::size_t i = 0;
  for (const StageTiming& t : sim->stage_timings()) fmt::print("{:>3}. {}\n", ++i, t.name);
  return kOk;
}

}  // namespace

std::optional<std::string> too_large_for_memory(const scene::RunEstimate& e) {
  const auto avail = scene::available_memory();
  if (!avail || e.bytes <= *avail) return std::nullopt;
  return fmt::format(
      "the scene needs about {} ({:.3g} points x {:.0f} B, {} columns each, plus the program) "
      "but only {} of memory is available; coarsen solver.cell_size or a body's spacing "
      "(points scale as 1/spacing^3)",
      scene::format_bytes(e.bytes), e.points, e.bytes_per_point, e.columns,
      scene::format_bytes(*avail));
}

int check_command(const std::filesystem::path& scene_file, const RunOptions& options) {
  // Under mpirun (allowed with --stages only, main.cpp) the estimate is not repeated per rank.
  if (options.stages && parallel::world().distributed()) return print_stages(scene_file, options);
  scene::Scene s;
  scene::RunEstimate e;
  if (refused(scene_file, [&] {
        s = scene::load_scene(scene_file, options.sets, scene::Points::defer);
        // Counting visits every lattice point; beyond 1e8 (about a second per 1e8) the volume
        // estimate is given instead, which is what the run's memory guard uses.
        auto bodies = scene::estimate_points(s);
        double total = 0.0;
        for (const auto& b : bodies) total += b.points;
        if (total <= 1e8) bodies = scene::count_and_check_points(s);
        e = scene::estimate_run(s, std::move(bodies));
      })) {
    return kBadInput;
  }
  const int threads = threads_used(options.threads);
  fmt::print("scene {} ({}): valid, method {}\n", s.name, scene_file.string(), s.method);
  if (s.solver.geometry == Geometry::axisymmetric) {
    fmt::print("axisymmetric (r-z): points in the half-plane y = 0, r = x > 0, each a ring\n");
  } else if (s.symmetry_axis >= 0) {
    fmt::print("half model: symmetry plane {} = 0, points on the positive side only\n",
               "xyz"[s.symmetry_axis]);
  }
  fmt::print("{:<16} {:>14} {:>12}  {}\n", "body", "points", "spacing_m", "material");
  for (std::size_t i = 0; i < s.bodies.size(); ++i) {
    const auto& b = s.bodies[i];
    const auto& be = e.bodies[i];
    fmt::print("{:<16} {:>14} {:>12.4g}  {} ({} / {}){}\n", b.name,
               be.counted ? fmt::format("{}", static_cast<std::size_t>(be.points))
                          : fmt::format("~{:.3g}", be.points),
               b.spacing, b.material.name, b.material.eos, b.material.strength,
               b.damage.model == "none" ? "" : ", damage " + b.damage.model);
  }
  for (const std::string& line : s.notes) fmt::print("{}\n", line);  // boulder fields
  for (const std::string& line : resolution_advice(s)) fmt::print("{}\n", line);
  const bool counted = !e.bodies.empty() && e.bodies.front().counted;
  fmt::print("points: {}{}\n",
             counted ? fmt::format("{}", static_cast<std::size_t>(e.points))
                     : fmt::format("~{:.3g} (from the bodies' volumes)", e.points),
             "");
  const auto avail = scene::available_memory();
  fmt::print("memory: ~{} ({} columns, ~{:.0f} B per point){}\n", scene::format_bytes(e.bytes),
             e.columns, e.bytes_per_point,
             avail ? fmt::format("; available {}", scene::format_bytes(*avail)) : "");
  fmt::print("time step: {:.4g} s at the start (Eq. 34, cfl {}); end time {} s: >= {:.3g} steps\n",
             e.dt_first, s.solver.cfl, s.end_time, e.steps);
  fmt::print(
      "run time: ~{} on {} thread{} (at least; shocks shorten the step, often 2-3x; rate "
      "1.2e6 point-steps/s per core, measured on scenes/lab-impact-coarse.toml)\n",
      format_duration(e.seconds_per_core / threads), threads, threads == 1 ? "" : "s");
  if (auto refusal = too_large_for_memory(e)) {
    spdlog::error("{}: {}", scene_file.string(), *refusal);
    return kBadInput;
  }
  return options.stages ? print_stages(scene_file, options) : kOk;
}

}  // namespace shatter::cli
