#include "run_loop.hpp"

#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <limits>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include "beta_output.hpp"
#include "commands.hpp"
#include "fragments_report.hpp"
#include "progress.hpp"
#include "progress_guard.hpp"
#include "shatter/io/columns.hpp"
#include "shatter/io/snapshot.hpp"
#include "shatter/io/timeseries.hpp"
#include "shatter/io/xdmf.hpp"
#include "shatter/mpm/simulation.hpp"
#include "shatter/parallel/comm.hpp"
#include "shatter/parallel/decomposition.hpp"
#include "shatter/scene/build.hpp"

#ifndef SHATTER_VERSION
#define SHATTER_VERSION "unknown"
#endif

namespace shatter::cli {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kNever = std::numeric_limits<double>::infinity();

// The signal that asked the run to stop (SIGINT or SIGTERM), 0 while none did. The handler only
// sets it: the run loop looks at it after each completed step, the one point where the state,
// the energy accounts and the output schedule agree, and writes the checkpoint there.
volatile std::sig_atomic_t g_stop_signal = 0;

extern "C" void request_stop(int sig) {
  g_stop_signal = sig;
}

// Installs request_stop for SIGINT and SIGTERM for the life of the run, restoring the previous
// handlers after. SA_RESETHAND: a second signal while the checkpoint is written takes the
// default action (the checkpoint is written to a temporary file and renamed, so the previous
// one stays valid).
class StopSignals {
 public:
  StopSignals() {
    g_stop_signal = 0;
    struct sigaction sa {};
    sa.sa_handler = request_stop;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESETHAND;
    sigaction(SIGINT, &sa, &old_int_);
    sigaction(SIGTERM, &sa, &old_term_);
  }
  ~StopSignals() {
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
  }
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

 private:
  struct sigaction old_int_ {};
  struct sigaction old_term_ {};
};

// Thrown out of the step loop when a stop signal arrived.
struct Stopped {
  int signal = 0;
};

class Runner {
 public:
  Runner(Solver& sim, const RunSpec& spec)
      : sim_(sim),
        spec_(spec),
        scene_(*spec.scene),
        series_(spec.out / "particles.xmf"),
        cursor_(spec.cursor),
        guard_(spec.scene->dt_floor_ratio,
               spec.resumed && spec.dt_first > 0.0 ? spec.dt_first : sim.clock().dt),
        start_wall_(Clock::now()),
        steps_at_last_(sim.clock().step),
        start_time_(sim.time()) {
    if (scene_.beta) beta_.emplace(*scene_.beta, spec.out);
    if (scene_.output.columns.empty()) {
      columns_ = io::all_columns(sim.particles());
    } else {
      columns_ = io::registered_subset(io::select_columns(scene_.output.columns), sim.particles());
    }
  }

  int run() {
    steps_at_start_ = sim_.clock().step;
    // On several ranks (docs/mpi.md) every rank steps and takes part in the gathers; rank 0
    // alone writes the files, which look like a single process's (rows sorted by particle id).
    if (root_) std::filesystem::create_directories(snapshot_dir(spec_.out));
    if (spec_.resumed) {
      if (root_ && !resume_timeseries()) return kBadInput;
      if (root_ && beta_ && !beta_->resume(sim_.time())) {
        if (dist_) comm_.abort(kBadInput);
        return kBadInput;
      }
      std::vector<std::filesystem::path> snaps;
      for (const auto& e : std::filesystem::directory_iterator(snapshot_dir(spec_.out))) {
        if (e.path().extension() == ".h5" && e.path().stem().string().rfind("snapshot_", 0) == 0) {
          snaps.push_back(e.path());
        }
      }
      if (root_) series_.rebuild(snaps, sim_.time());
      // The checkpoint was written after the snapshot and the row of its own time, if any.
      last_snapshot_time_ = sim_.time();
      last_checkpoint_time_ = sim_.time();
      last_row_step_ = sim_.clock().step;
      rows_written_ = true;
      // The end time may have been changed on the command line.
      if (scene_.output.snapshot_every > 0) {
        cursor_.next_snapshot_time =
            on_end(cursor_.next_snapshot_time, scene_.output.snapshot_every);
      }
      if (scene_.output.checkpoint_every > 0) {
        cursor_.next_checkpoint_time =
            on_end(cursor_.next_checkpoint_time, scene_.output.checkpoint_every);
      }
    } else {
      if (root_) timeseries_.emplace(spec_.out / "timeseries.csv", porous(), beta_.has_value());
      cursor_.next_snapshot = 0;
      cursor_.next_snapshot_time = 0.0;
      cursor_.next_checkpoint_time =
          scene_.output.checkpoint_every > 0 ? scene_.output.checkpoint_every : kNever;
      write_row();
    }
    try {
      guard_.check(sim_.clock(), sim_.energy(), sim_.particles());
      loop();
    } catch (const NumericalError& e) {
      return post_mortem(e);
    } catch (const Stopped& s) {
      return stopped(s.signal);
    }
    finish();
    return kOk;
  }

 private:
  void loop() {
    const double end = scene_.end_time;
    if (cursor_.next_snapshot_time <= sim_.time()) snapshot();
    while (sim_.time() < end) {
      const double target =
          std::min({cursor_.next_snapshot_time, cursor_.next_checkpoint_time, end});
      while (sim_.time() < target) {
        // Plain steps until the next one would pass the output time; advance_to then shortens
        // the last step to land on it.
        const double before = sim_.time();
        if (sim_.time() + sim_.clock().dt >= target) {
          sim_.advance_to(target);
        } else {
          sim_.step();
        }
        guard_.check(sim_.clock(), sim_.energy(), sim_.particles(), before);
        if (sim_.clock().step % static_cast<std::uint64_t>(scene_.output.timeseries_every) == 0) {
          write_row();
        }
        progress();
        int stop = g_stop_signal;
        // every rank stops after the same step (mpirun forwards the signal to all of them)
        if (dist_) stop = static_cast<int>(comm_.max(static_cast<double>(stop)));
        if (stop != 0) throw Stopped{stop};
      }
      if (sim_.time() >= cursor_.next_snapshot_time) snapshot();
      if (sim_.time() >= cursor_.next_checkpoint_time) {
        checkpoint();
        cursor_.next_checkpoint_time =
            on_end(cursor_.next_checkpoint_time + scene_.output.checkpoint_every,
                   scene_.output.checkpoint_every);
      }
    }
  }

  // The time series continued from the checkpoint's last row; false (after saying why) when
  // rows it covers are lost and the spec does not accept the gap.
  bool resume_timeseries() {
    try {
      timeseries_.emplace(spec_.out / "timeseries.csv", spec_.rows, porous(), beta_.has_value());
    } catch (const io::TimeSeriesGap& e) {
      spdlog::error("{}", e.what());
      if (dist_) comm_.abort(kBadInput);
      return false;
    }
    if (!timeseries_->note().empty()) spdlog::warn("{}", timeseries_->note());
    return true;
  }

  void finish() {
    // The last state is always on disk, whatever the cadence.
    if (last_snapshot_time_ != sim_.time()) snapshot();
    write_row();
    cursor_.next_checkpoint_time = kNever;
    if (last_checkpoint_time_ != sim_.time()) checkpoint();
    if (root_) timeseries_->sync();
    if (root_ && beta_) beta_->write();
    const double wall = seconds_since_start();
    spdlog::info("finished: t = {}, {} steps, {:.1f} s wall, energy error {:.3e}",
                 format_time(sim_.time()), sim_.clock().step, wall, sim_.energy().error());
    report_parallel();
    if (scene_.output.fragments && sim_.particles().has(Field::damage)) {
      FragmentReportInfo info{sim_.time(), {}, {}, false};
      for (const auto& b : scene_.bodies) {
        info.body_names.push_back(b.name);
        info.body_materials.push_back(b.material.name);
      }
      // On several ranks: the search runs on rank 0 over the gathered particles, so fragments
      // that straddle rank boundaries are found whole (docs/mpi.md: its memory limit).
      const ParticleStore& all = all_particles();
      if (root_) {
        report_fragments(all, scene_.symmetry_axis, scene_.fracture.search, spec_.out / "fragments",
                         info);
      }
    }
  }

  // An output time that misses the end time by round-off (5 x 1e-6 != 5e-6) is the end time;
  // otherwise the run would take a sliver step and write the end state twice.
  // On several ranks (or with SHATTER_STAGE_TIMES set): the exchange traffic summed over the
  // ranks and each stage's time, the slowest rank's (docs/mpi.md takes its figures from these).
  void report_parallel() {
    const auto* mpm = dynamic_cast<const Simulation*>(&sim_);
    if (mpm == nullptr || (!dist_ && std::getenv("SHATTER_STAGE_TIMES") == nullptr)) return;
    const parallel::Traffic h = mpm->halo_traffic(), m = mpm->migrate_traffic();
    std::int64_t t[4] = {static_cast<std::int64_t>(h.bytes), static_cast<std::int64_t>(h.messages),
                         static_cast<std::int64_t>(m.bytes), static_cast<std::int64_t>(m.messages)};
    comm_.sum(t);
    const auto steps =
        static_cast<double>(std::max<std::uint64_t>(1, sim_.clock().step - steps_at_start_));
    std::vector<double> times;
    for (const auto& st : sim_.stage_timings()) times.push_back(st.seconds);
    times.push_back(h.seconds);
    times.push_back(m.seconds);
    comm_.max(times);
    spdlog::info(
        "mpi: {} ranks, {} steps; halo {:.0f} bytes and {:.1f} messages per step (all ranks), "
        "migration {:.0f} bytes and {:.2f} messages per step, {} recuts",
        comm_.size(), sim_.clock().step - steps_at_start_, static_cast<double>(t[0]) / steps,
        static_cast<double>(t[1]) / steps, static_cast<double>(t[2]) / steps,
        static_cast<double>(t[3]) / steps, mpm->rebalances());
    std::string line;
    const auto& st = sim_.stage_timings();
    for (std::size_t i = 0; i < st.size(); ++i) {
      line += fmt::format(" {} {:.3g}", st[i].name, 1e3 * times[i] / steps);
    }
    spdlog::info(
        "stage ms per step (slowest rank):{}; of which in exchanges: halo {:.3g}, "
        "migration {:.3g}",
        line, 1e3 * times[st.size()] / steps, 1e3 * times[st.size() + 1] / steps);
  }

  double on_end(double t, double cadence) const {
    return std::abs(t - scene_.end_time) <= 1e-9 * cadence ? scene_.end_time : t;
  }

  void snapshot() {
    const auto file =
        snapshot_dir(spec_.out) / fmt::format("snapshot_{:06d}.h5", cursor_.next_snapshot);
    io::SnapshotOptions options;
    options.single_precision = scene_.output.single_precision;
    // Group g holds body g, whose material is material g (scene/build.cpp).
    for (const auto& b : scene_.bodies) {
      options.body_names.push_back(b.name);
      options.material_names.push_back(b.material.name);
    }
    const ParticleStore& all = all_particles();
    if (root_) {
      io::write_snapshot(file, all,
                         {sim_.time(), sim_.clock().step, SHATTER_VERSION, scene_.symmetry_axis},
                         columns_, options);
      series_.add(file);
    }
    last_snapshot_time_ = sim_.time();
    ++cursor_.next_snapshot;
    // Times from the index, not by accumulation, so they do not drift.
    cursor_.next_snapshot_time =
        scene_.output.snapshot_every > 0
            ? on_end(static_cast<double>(cursor_.next_snapshot) * scene_.output.snapshot_every,
                     scene_.output.snapshot_every)
            : kNever;
    spdlog::debug("snapshot {} at t = {}", file.string(), format_time(sim_.time()));
  }

  void checkpoint() {
    // The rows the checkpoint covers reach the disk before it is committed: a crash right after
    // the commit must not lose them (a resume keeps the rows up to the checkpoint's time).
    if (root_) timeseries_->sync();
    if (root_ && beta_) beta_->write();  // the launches this checkpoint covers
    io::RunState state;
    state.clock = sim_.clock();
    state.energy = sim_.energy();
    state.internal_next = sim_.internal_next();
    state.dt_first = guard_.dt_first();
    state.cursor = cursor_;
    state.scene_text = scene_.resolved;
    state.program_version = SHATTER_VERSION;
    const ParticleStore& all = all_particles();
    if (root_) io::write_checkpoint(checkpoint_path(spec_.out), all, state);
    last_checkpoint_time_ = sim_.time();
    spdlog::info("checkpoint at t = {} (step {})", format_time(sim_.time()), sim_.clock().step);
  }

  double failure_ratio() const {
    if (dist_) return last_failure_ratio_;  // of the last row (progress() makes no collective)
    if (scene_.solver.geometry == Geometry::axisymmetric)  // a point is a ring: weigh by mass
      return io::failed_mass_fraction(sim_.particles(), scene_.fracture.threshold, spec_.damaged);
    return io::failure_ratio(sim_.particles(), scene_.fracture.threshold, spec_.damaged);
  }

  // Every particle, on rank 0: the local store with one rank, a gather sorted by id otherwise.
  const ParticleStore& all_particles() {
    if (!dist_) return sim_.particles();
    gathered_ = parallel::gather_particles(sim_.particles(), comm_);
    return gathered_;
  }

  void write_row() {
    if (last_row_step_ == sim_.clock().step && rows_written_) return;
    last_row_step_ = sim_.clock().step;
    rows_written_ = true;
    io::TimeSeriesRow r;
    r.step = sim_.clock().step;
    r.time = sim_.time();
    r.dt = sim_.clock().dt_prev;
    r.energy = sim_.energy();
    if (dist_) {
      // exact sums over the ranks: the same bits as one process
      auto p = io::momentum_sums(sim_.particles());
      constexpr int L = parallel::ExactSum::kLimbs;
      std::vector<std::int64_t> limbs(3 * L + 2);
      for (int d = 0; d < 3; ++d) {
        p[static_cast<std::size_t>(d)].normalise();
        std::copy(p[static_cast<std::size_t>(d)].limbs().begin(),
                  p[static_cast<std::size_t>(d)].limbs().end(), limbs.begin() + d * L);
      }
      const auto c = io::failure_counts(sim_.particles(), scene_.fracture.threshold, spec_.damaged);
      limbs[3 * L] = c[0];
      limbs[3 * L + 1] = c[1];
      comm_.sum(limbs);
      for (int d = 0; d < 3; ++d) {
        std::copy(limbs.begin() + d * L, limbs.begin() + (d + 1) * L,
                  p[static_cast<std::size_t>(d)].limbs().begin());
      }
      r.momentum = {p[0].value(), p[1].value(), p[2].value()};
      last_failure_ratio_ = limbs[3 * L + 1] == 0 ? 0.0
                                                  : static_cast<double>(limbs[3 * L]) /
                                                        static_cast<double>(limbs[3 * L + 1]);
      r.failure_ratio = last_failure_ratio_;
    } else {
      r.momentum = io::total_momentum(sim_.particles());
      r.failure_ratio = failure_ratio();
    }
    if (porous()) porosity_columns(r);
    if (beta_) {
      beta_->sample(
          r, sim_.time(), sim_.particles(),
          [this]() -> const ParticleStore& { return all_particles(); }, comm_);
    }
    r.wall = seconds_since_start();
    if (root_) timeseries_->write(r);
  }

  // The time series' mean porosity and compaction work (issue 29): exact sums, added over the
  // ranks as the momentum above, so the same bits on any rank count.
  void porosity_columns(io::TimeSeriesRow& r) {
    auto phi = io::porosity_sums(sim_.particles());
    if (dist_) {
      constexpr int L = parallel::ExactSum::kLimbs;
      std::vector<std::int64_t> limbs(3 * L);
      for (std::size_t k = 0; k < 3; ++k) {
        phi[k].normalise();
        std::copy(phi[k].limbs().begin(), phi[k].limbs().end(),
                  limbs.begin() + static_cast<long>(k) * L);
      }
      comm_.sum(limbs);
      for (std::size_t k = 0; k < 3; ++k) {
        std::copy(limbs.begin() + static_cast<long>(k) * L,
                  limbs.begin() + static_cast<long>(k + 1) * L, phi[k].limbs().begin());
      }
    }
    r.mean_porosity = io::mean_porosity(phi);
    r.compaction_work = phi[2].value();
  }

  // A porous material is in the scene (its distension column, issue 29): the time series then
  // has mean_porosity.
  bool porous() const { return sim_.particles().has(Field::distension); }

  void progress() {
    const auto now = Clock::now();
    if (std::chrono::duration<double>(now - last_progress_).count() <
        scene_.output.progress_every) {
      return;
    }
    const double wall = seconds_since_start();
    const double done = sim_.time() - start_time_;
    const double eta = done > 0 ? (scene_.end_time - sim_.time()) / done * wall : kNever;
    const double since = std::chrono::duration<double>(now - last_progress_).count();
    const double rate =
        since > 0 ? static_cast<double>(sim_.clock().step - steps_at_last_) / since : 0.0;
    spdlog::info(
        "t = {} / {} | step {} | dt {:.3g} s | {:.0f} steps/s | ETA {} | energy error "
        "{:.2e} | failed {:.1f}%",
        format_time(sim_.time()), format_time(scene_.end_time), sim_.clock().step, sim_.clock().dt,
        rate, format_duration(eta), sim_.energy().error(), 100.0 * failure_ratio());
    last_progress_ = now;
    steps_at_last_ = sim_.clock().step;
  }

  // A stop signal: the state after the last completed step goes to the checkpoint, with the
  // command that continues the run. Exit status 128 + signal, as a shell reports a killed job.
  int stopped(int sig) {
    const char* name = sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "signal";
    spdlog::warn("{} received: stopping after step {} (t = {})", name, sim_.clock().step,
                 format_time(sim_.time()));
    try {
      write_row();
      checkpoint();
      if (root_) timeseries_->sync();
    } catch (const std::exception& w) {
      spdlog::error("could not write the checkpoint: {}", w.what());
      return 128 + sig;
    }
    const auto cp = checkpoint_path(spec_.out);
    spdlog::warn("stopped at t = {:.17g} s (step {}); checkpoint: {}", sim_.time(),
                 sim_.clock().step, cp.string());
    spdlog::warn("continue with: shatter resume {}", cp.string());
    return 128 + sig;
  }

  int post_mortem(const NumericalError& e) {
    const auto file = spec_.out / fmt::format("failed_step{}.h5", e.step());
    spdlog::error("numerical failure at step {} (t = {}), particle {}: {}", e.step(),
                  format_time(sim_.time()), e.particle(), e.what());
    try {
      const ParticleStore& all = all_particles();
      if (root_) {
        io::write_snapshot(file, all,
                           {sim_.time(), e.step(), SHATTER_VERSION, scene_.symmetry_axis},
                           io::all_columns(all));
        spdlog::error("state written for post-mortem: {}", file.string());
      }
    } catch (const std::exception& w) {
      spdlog::error("could not write the post-mortem snapshot: {}", w.what());
    }
    try {
      if (root_) timeseries_->sync();
    } catch (const std::exception& w) {
      spdlog::error("{}", w.what());
    }
    return kNumerical;
  }

  double seconds_since_start() const {
    return std::chrono::duration<double>(Clock::now() - start_wall_).count();
  }

  Solver& sim_;
  const RunSpec& spec_;
  const scene::Scene& scene_;
  io::XdmfSeries series_;
  io::OutputCursor cursor_;
  io::ColumnSelection columns_;
  std::optional<io::TimeSeriesWriter> timeseries_;
  ProgressGuard guard_;
  Clock::time_point start_wall_;
  Clock::time_point last_progress_ = Clock::now();
  std::uint64_t steps_at_last_;
  double start_time_ = 0.0;
  double last_snapshot_time_ = -1.0;
  double last_checkpoint_time_ = -1.0;
  std::uint64_t last_row_step_ = 0;
  bool rows_written_ = false;
  const parallel::Comm& comm_ = parallel::world();
  const bool root_ = parallel::world().rank() == 0;
  const bool dist_ = parallel::world().distributed();
  double last_failure_ratio_ = 0.0;
  std::uint64_t steps_at_start_ = 0;
  ParticleStore gathered_;
  std::optional<BetaOutput> beta_;  // [beta] scenes (issue 32)
};

}  // namespace

std::string unusable_run_directory(const std::filesystem::path& out, const std::string& what) {
  namespace fs = std::filesystem;
  if (out.empty()) return fmt::format("{}: the run directory must not be empty", what);
  std::error_code ec;
  const auto status = fs::status(out, ec);
  if (fs::exists(status) && !fs::is_directory(status)) {
    return fmt::format("{} {}: exists and is not a directory", what, out.string());
  }
  // The directory itself, or the nearest existing folder above it, must let us create files.
  fs::path probe = fs::absolute(out, ec);
  while (!fs::exists(probe, ec) && probe.has_parent_path() && probe != probe.parent_path()) {
    probe = probe.parent_path();
  }
  if (!fs::is_directory(probe, ec)) {
    return fmt::format("{} {}: {} is not a directory", what, out.string(), probe.string());
  }
  if (::access(probe.c_str(), W_OK | X_OK) != 0) {
    return fmt::format("{} {}: cannot write in {} ({})", what, out.string(), probe.string(),
                       std::strerror(errno));
  }
  return {};
}

std::unique_ptr<io::RunLock> lock_run_directory(const std::filesystem::path& out, bool take_over) {
  if (parallel::world().rank() != 0) return nullptr;
  std::string stale;
  auto lock = std::make_unique<io::RunLock>(out, take_over, &stale);
  if (!stale.empty()) {
    spdlog::warn("{}: took over the lock of {}, which ended without releasing it (killed?)",
                 out.string(), stale);
  }
  return lock;
}

bool lock_or_refuse(const std::filesystem::path& out, bool take_over,
                    std::unique_ptr<io::RunLock>& lock) {
  try {
    lock = lock_run_directory(out, take_over);
  } catch (const io::RunLocked& e) {
    spdlog::error("{}", e.what());
    if (parallel::world().distributed()) parallel::world().abort(kBadInput);
    return false;
  }
  return true;
}

std::unique_ptr<Solver> make_solver_or_refuse(const scene::Scene& s, ParticleStore particles,
                                              const std::vector<MaterialPtr>& materials,
                                              int threads, const std::filesystem::path& source) {
  try {
    return scene::make_solver(s, std::move(particles), materials, threads);
  } catch (const std::invalid_argument& e) {
    spdlog::error("{}: {}", source.string(), e.what());
    return nullptr;
  }
}

bool refuse_method_on_ranks(const Solver& sim, const std::filesystem::path& source) {
  if (!parallel::world().distributed() || sim.method() == "mpm") return false;
  if (parallel::world().rank() == 0) {
    spdlog::error("{}: method '{}' runs on one rank only (the MPI decomposition is MPM's)",
                  source.string(), sim.method());
  }
  return true;
}

std::filesystem::path snapshot_dir(const std::filesystem::path& out) {
  return out / "snapshots";
}
std::filesystem::path checkpoint_path(const std::filesystem::path& out) {
  return out / "checkpoint.h5";
}

int run_loop(Solver& sim, const RunSpec& spec) {
  const StopSignals signals;
  return Runner(sim, spec).run();
}

}  // namespace shatter::cli
