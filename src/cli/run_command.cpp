#include <spdlog/spdlog.h>

#include "commands.hpp"
#include "refused.hpp"
#include "run_loop.hpp"
#include "shatter/io/atomic_file.hpp"
#include "shatter/parallel/comm.hpp"
#include "shatter/scene/build.hpp"
#include "shatter/scene/estimate.hpp"

#ifndef SHATTER_VERSION
#define SHATTER_VERSION "unknown"
#endif

namespace shatter::cli {
namespace {

// Files a run writes; --overwrite removes exactly these, nothing else in the directory.
bool holds_a_run(const std::filesystem::path& out) {
  return std::filesystem::exists(out / "scene.toml") ||
         std::filesystem::exists(checkpoint_path(out)) ||
         std::filesystem::exists(snapshot_dir(out));
}

void clear_run(const std::filesystem::path& out) {
  std::filesystem::remove_all(snapshot_dir(out));
  for (const char* name : {"scene.toml", "checkpoint.h5", "checkpoint.h5.tmp", "particles.xmf",
                           "timeseries.csv", "fragments.csv", "fragments.h5", "fragments.ss",
                           "particles_cells.h5", "fragments_bound.json"}) {
    std::filesystem::remove(out / name);
  }
  for (const auto& e : std::filesystem::directory_iterator(out)) {
    if (e.path().filename().string().rfind("failed_step", 0) == 0)
      std::filesystem::remove(e.path());
  }
}

std::string resolved_header(const std::filesystem::path& scene_file,
                            const std::vector<std::string>& sets, const scene::Scene& s) {
  std::string h =
      fmt::format("# Resolved by shatter {} from {}\n", SHATTER_VERSION, scene_file.string());
  for (const auto& o : sets) h += fmt::format("#   --set {}\n", o);
  for (const auto& b : s.bodies) {
    h += fmt::format(
        "# body {}: {} points, spacing {} m, volume {:.6g} m^3, velocity [{}, {}, {}] m/s\n",
        b.name, b.fill.points.size(), b.spacing, b.fill.volume, b.velocity.x(), b.velocity.y(),
        b.velocity.z());
  }
  if (s.impact.used) {
    const auto& c = s.impact.projectile_centre;
    h += fmt::format("# impact: projectile centre [{}, {}, {}] m, impact point [{}, {}, {}] m\n",
                     c.x(), c.y(), c.z(), s.impact.impact_point.x(), s.impact.impact_point.y(),
                     s.impact.impact_point.z());
  }
  return h + "\n";
}

// Why the run directory cannot take this run (checked before the scene is filled with points,
// which can take minutes for a large one); none under --check, which writes nothing.
std::optional<std::string> refused_directory(const scene::Scene& s, const RunOptions& options) {
  const std::filesystem::path out = options.out.value_or(s.output.directory);
  if (options.check) return std::nullopt;
  std::string bad = unusable_run_directory(out, options.out ? "--out" : "output.directory");
  if (!bad.empty()) return bad;
  if (std::filesystem::exists(out) && holds_a_run(out) && !options.overwrite) {
    return fmt::format(
        "{} already holds a run; pass --overwrite to replace it or --out for another "
        "directory",
        out.string());
  }
  return std::nullopt;
}

// The size of the run is checked before any point is created: a scene larger than the machine
// is refused with its size instead of dying in std::bad_alloc. An estimate that cannot be made
// (a solver setting refused) leaves the refusal to the set-up, which names the cause.
bool refuse_too_large(const scene::Scene& s, const std::filesystem::path& scene_file) {
  std::optional<scene::RunEstimate> estimate;
  try {
    estimate = scene::estimate_run(s, scene::estimate_points(s));
  } catch (const std::invalid_argument&) {
  }
  if (auto refusal = estimate ? too_large_for_memory(*estimate) : std::nullopt) {
    spdlog::error("{}: {} (shatter check {} prints the estimate)", scene_file.string(), *refusal,
                  scene_file.string());
    return true;
  }
  return false;
}

// Loads, checks and builds the scene: everything that can refuse the input happens before the
// run directory is touched. kOk, or kBadInput after reporting why.
int load_scene(const std::filesystem::path& scene_file, const RunOptions& options, scene::Scene& s,
               scene::BuiltScene& built) {
  bool stop = false;
  const bool bad_scene = refused(scene_file, [&] {
    s = scene::load_scene(scene_file, options.sets, scene::Points::defer);
    if (auto bad = refused_directory(s, options)) {
      spdlog::error("{}", *bad);
      stop = true;
    } else if (refuse_too_large(s, scene_file)) {
      stop = true;
    } else {
      scene::fill_bodies(s);
      built = scene::build(s);
    }
  });
  return bad_scene || stop ? kBadInput : kOk;
}

void log_scene(const scene::Scene& s, const std::filesystem::path& scene_file) {
  spdlog::info("scene {} ({}): {} points in {} bodies, end time {} s", s.name, scene_file.string(),
               s.particle_count(), s.bodies.size(), s.end_time);
  // Which catalogue: a copied binary finds the one it was installed with, not the source tree's.
  spdlog::info("  materials from {}", s.catalogue_file.string());
  for (const auto& b : s.bodies) {
    spdlog::info("  body {}: {} ({} / {}), {} points, spacing {} m", b.name, b.material.name,
                 b.material.eos, b.material.strength, b.fill.points.size(), b.spacing);
  }
}

// Creates and locks the run directory, clears a previous run under --overwrite and writes the
// resolved scene. On several ranks rank 0 alone writes (docs/mpi.md); every rank has checked
// the directory before, ahead of the solver's collective set-up. False after reporting a refusal.
bool prepare_run_directory(const std::filesystem::path& out,
                           const std::filesystem::path& scene_file, const RunOptions& options,
                           const scene::Scene& s, std::unique_ptr<io::RunLock>& lock) {
  const bool root = parallel::world().rank() == 0;
  try {
    if (root) std::filesystem::create_directories(out);
  } catch (const std::filesystem::filesystem_error& e) {
    spdlog::error("{} {}: cannot create the run directory ({})",
                  options.out ? "--out" : "output.directory", out.string(), e.code().message());
    if (parallel::world().distributed()) parallel::world().abort(kBadInput);
    return false;
  }
  if (!lock_or_refuse(out, options.take_lock, lock)) return false;
  if (options.overwrite && root) clear_run(out);
  if (root) {
    io::write_text_atomically(out / "scene.toml",
                              resolved_header(scene_file, options.sets, s) + s.resolved);
  }
  parallel::world().barrier();
  return true;
}

}  // namespace

int run_command(const std::filesystem::path& scene_file, const RunOptions& options) {
  scene::Scene s;
  scene::BuiltScene built;
  if (load_scene(scene_file, options, s, built) != kOk) return kBadInput;
  const std::filesystem::path out = options.out.value_or(s.output.directory);
  log_scene(s, scene_file);
  std::unique_ptr<Solver> sim = make_solver_or_refuse(s, std::move(built.particles),
                                                      built.materials, options.threads, scene_file);
  if (!sim) return kBadInput;
  spdlog::info("method {}", sim->method());
  if (refuse_method_on_ranks(*sim, scene_file)) return kBadInput;
  if (parallel::world().distributed()) {
    spdlog::info("{} MPI ranks: grid blocks decomposed along a Morton curve (docs/mpi.md)",
                 parallel::world().size());
  }
  if (options.check) {
    spdlog::info("scene {} is valid: {} points, first time step {:.6g} s (--check: nothing run)",
                 scene_file.string(), s.particle_count(), sim->clock().dt);
    return kOk;
  }
  // Held to the end of the run: a second process in the directory is refused (io::RunLock).
  std::unique_ptr<io::RunLock> lock;
  if (!prepare_run_directory(out, scene_file, options, s, lock)) return kBadInput;
  spdlog::info("output in {}", out.string());

  RunSpec spec;
  spec.scene = &s;
  spec.out = out;
  spec.damaged = built.damaged;
  return run_loop(*sim, spec);
}

}  // namespace shatter::cli
