#include <algorithm>
#include <cmath>
#include <limits>

#include <spdlog/spdlog.h>

#include "commands.hpp"
#include "run_loop.hpp"
#include "shatter/io/checkpoint.hpp"
#include "shatter/parallel/comm.hpp"
#include "shatter/scene/build.hpp"

namespace shatter::cli {
namespace {

// A resumed run continues bit for bit only if the physics is unchanged: only the end time, the
// output settings and the MPI load balancing (no bit depends on the cut, docs/mpi.md) may be
// overridden.
bool allowed_on_resume(const std::string& assignment) {
  return assignment.rfind("output.", 0) == 0 || assignment.rfind("solver.end_time=", 0) == 0 ||
         assignment.rfind("solver.mpi.", 0) == 0;
}

// The step of the last time-series row the checkpoint covers: the rows the run wrote on its own
// cadence (the scene as it ran, before this resume's --set), plus the last row of a run that
// ended there. A row a stop signal wrote at another step is not one an uninterrupted run writes.
std::uint64_t rows_covered(const io::Checkpoint& c, const std::filesystem::path& file,
                           bool at_end) {
  const std::uint64_t step = c.state.clock.step;
  if (at_end) return step;
  const scene::Scene ran = scene::parse_scene(c.state.scene_text, file.string() + " (scene)", {});
  const auto every =
      static_cast<std::uint64_t>(std::max<std::int64_t>(1, ran.output.timeseries_every));
  return step / every * every;
}

// A --set that would change the physics (reported), or a directory given for the checkpoint.
bool refuse_arguments(const std::filesystem::path& file, const RunOptions& options) {
  for (const auto& o : options.sets) {
    if (!allowed_on_resume(o)) {
      spdlog::error(
          "--set {}: a resumed run may change only solver.end_time, output.* and solver.mpi.* "
          "(the rest would break the bit-for-bit continuation)",
          o);
      return true;
    }
  }
  if (std::filesystem::is_directory(file)) {
    const auto inside = checkpoint_path(file);
    spdlog::error("{} is a directory, not a checkpoint{}", file.string(),
                  std::filesystem::exists(inside)
                      ? fmt::format(" (its run's checkpoint: {})", inside.string())
                      : "");
    return true;
  }
  return false;
}

// The checkpoint, its scene (with this resume's --set) and the materials; false after
// reporting why they cannot be read.
bool read_inputs(const std::filesystem::path& file, const RunOptions& options, io::Checkpoint& c,
                 scene::Scene& s, std::vector<MaterialPtr>& materials) {
  try {
    c = io::read_checkpoint(file);
    s = scene::parse_scene(c.state.scene_text, file.string() + " (scene)", options.sets);
    materials = scene::build_materials(s);
  } catch (const scene::SceneError& e) {
    spdlog::error("{}", e.what());
    return false;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return false;
  }
  return true;
}

// Says what the resume will do: complete a run that reached its end time, or continue it.
void announce(const io::Checkpoint& c, const scene::Scene& s, const std::filesystem::path& file,
              bool at_end) {
  if (at_end) {
    // The run wrote its last checkpoint and may have died before what follows it (the fragment
    // catalogue): do that part again, it is deterministic.
    spdlog::info(
        "{} is at the end time {} s: completing the run's last outputs (to continue, raise the "
        "end time with --set solver.end_time=...)",
        file.string(), s.end_time);
  } else {
    spdlog::info("resuming {} from {} at t = {} s, step {} ({} points)", s.name, file.string(),
                 c.state.clock.time, c.state.clock.step, c.particles.size());
  }
}

// The checkpoint's columns, clock and energy books into the new solver.
void restore_state(Solver& sim, const io::Checkpoint& c) {
  // On several ranks each rank takes its own particles' columns, matched by id.
  io::restore_columns(sim.particles(), c.particles);
  if (std::isnan(c.state.internal_next)) {
    sim.restore(c.state.clock, c.state.energy);  // format-1 checkpoint: summed again
  } else {
    sim.restore(c.state.clock, c.state.energy, c.state.internal_next);
  }
}

// Where the run loop stands: the output schedule, the first step's dt, the rows covered.
RunSpec resume_spec(const io::Checkpoint& c, const scene::Scene& s,
                    const std::filesystem::path& file, const std::filesystem::path& out,
                    const RunOptions& options, bool at_end) {
  RunSpec spec;
  spec.scene = &s;
  spec.out = out;
  spec.damaged = scene::damaged_groups(s);
  spec.resumed = true;
  spec.cursor = c.state.cursor;
  spec.dt_first = c.state.dt_first;
  spec.rows = {rows_covered(c, file, at_end), options.accept_timeseries_gap};
  if (!options.sets.empty()) {
    // The output cadence may have changed: the next multiples of the cadences after now.
    const double t = c.state.clock.time;
    auto next_multiple = [t](double every) {
      if (!(every > 0)) return std::numeric_limits<double>::infinity();
      return (std::floor(t / every * (1.0 + 1e-12)) + 1.0) * every;
    };
    spec.cursor.next_snapshot_time = next_multiple(s.output.snapshot_every);
    spec.cursor.next_checkpoint_time = next_multiple(s.output.checkpoint_every);
  }
  return spec;
}

}  // namespace

int resume_command(const std::filesystem::path& file, const RunOptions& options) {
  if (refuse_arguments(file, options)) return kBadInput;
  io::Checkpoint c;
  scene::Scene s;
  std::vector<MaterialPtr> materials;
  if (!read_inputs(file, options, c, s, materials)) return kBadInput;
  const bool at_end = c.state.clock.time == s.end_time;
  if (c.state.clock.time > s.end_time) {
    spdlog::error(
        "{} is at t = {} s, after the end time {} s (raise it with --set "
        "solver.end_time=...)",
        file.string(), c.state.clock.time, s.end_time);
    return kBadInput;
  }
  const std::filesystem::path out =
      options.out.value_or(file.has_parent_path() ? file.parent_path() : ".");
  announce(c, s, file, at_end);

  if (const std::string bad =
          unusable_run_directory(out, options.out ? "--out" : "the checkpoint's directory");
      !bad.empty()) {
    spdlog::error("{}", bad);
    return kBadInput;
  }
  // Held to the end of the run: two resumes of one checkpoint would interleave the time series.
  std::unique_ptr<io::RunLock> lock;
  if (!lock_or_refuse(out, options.take_lock, lock)) return kBadInput;

  std::unique_ptr<Solver> sim =
      make_solver_or_refuse(s, ParticleStore(c.particles), materials, options.threads, file);
  if (!sim || refuse_method_on_ranks(*sim, file)) return kBadInput;
  restore_state(*sim, c);
  return run_loop(*sim, resume_spec(c, s, file, out, options, at_end));
}

}  // namespace shatter::cli
