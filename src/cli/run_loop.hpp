#pragma once
// The run loop shared by `run` and `resume`: steps the simulation, writes snapshots (with the
// XDMF sidecar), checkpoints and the time series on their schedules, prints progress, and on a
// numerical failure writes a post-mortem snapshot.

#include <filesystem>
#include <limits>
#include <memory>
#include <vector>

#include "shatter/core/solver.hpp"
#include "shatter/io/checkpoint.hpp"
#include "shatter/io/run_lock.hpp"
#include "shatter/io/timeseries.hpp"
#include "shatter/scene/scene.hpp"

namespace shatter::cli {

struct RunSpec {
  const scene::Scene* scene = nullptr;
  std::filesystem::path out;
  std::vector<bool> damaged;  // per group: counts in the failure ratio
  bool resumed = false;
  io::OutputCursor cursor;  // where the schedule stands (resume)
  double dt_first = 0.0;    // first step's dt of the run (resume; 0 = this state's)
  io::ResumeRows rows;      // the time-series rows the checkpoint covers (resume)
  double internal_next = std::numeric_limits<double>::quiet_NaN();  // see io::RunState
};

// Runs to the scene's end time; returns the exit status.
int run_loop(Solver& sim, const RunSpec& spec);

// Why `out` cannot be a run directory (an existing file, or a place this process may not create
// or write in), naming `what` (e.g. "--out" or "output.directory"); empty when it can. Checked
// before anything is written.
std::string unusable_run_directory(const std::filesystem::path& out, const std::string& what);

// Locks the run directory `out` for this process (io::RunLock; rank 0 alone holds it). Null on
// the other ranks; throws io::RunLocked when another process holds it, after reporting a stale
// lock it took over.
std::unique_ptr<io::RunLock> lock_run_directory(const std::filesystem::path& out, bool take_over);

// lock_run_directory for `shatter run` and `resume`: the lock in `lock`, or false when another
// process holds the directory (reported; on several MPI ranks every rank is aborted).
bool lock_or_refuse(const std::filesystem::path& out, bool take_over,
                    std::unique_ptr<io::RunLock>& lock);

// scene::make_solver for `shatter run` and `resume`: null when the set-up refuses the scene
// (reported, naming `source`, the scene or checkpoint file).
std::unique_ptr<Solver> make_solver_or_refuse(const scene::Scene& s, ParticleStore particles,
                                              const std::vector<MaterialPtr>& materials,
                                              int threads, const std::filesystem::path& source);

// True (reported by rank 0) when this is an MPI run and the solver's method runs on one rank only.
bool refuse_method_on_ranks(const Solver& sim, const std::filesystem::path& source);

// Paths inside a run directory.
std::filesystem::path snapshot_dir(const std::filesystem::path& out);
std::filesystem::path checkpoint_path(const std::filesystem::path& out);

}  // namespace shatter::cli
