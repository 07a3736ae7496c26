// shatter: run, resume and post-process MPM impact simulations.

#include <spdlog/sinks/basic_file_sink.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <algorithm>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "commands.hpp"
#include "shatter/io/atomic_file.hpp"
#include "shatter/io/suggest.hpp"
#include "shatter/parallel/comm.hpp"

#ifndef SHATTER_VERSION
#define SHATTER_VERSION "unknown"
#endif

namespace {

void setup_logging(bool quiet, const std::string& log_file) {
  // On several ranks rank 0 logs as one process does; the others only their errors, each line
  // naming the rank (docs/mpi.md).
  const auto& world = shatter::parallel::world();
  const bool other_rank = world.rank() != 0;
  std::vector<spdlog::sink_ptr> sinks;
  auto console = std::make_shared<spdlog::sinks::stderr_color_sink_mt>();
  console->set_level(other_rank ? spdlog::level::err
                     : quiet    ? spdlog::level::warn
                                : spdlog::level::info);
  sinks.push_back(console);
  if (!log_file.empty() && !other_rank) {
    auto file = std::make_shared<spdlog::sinks::basic_file_sink_mt>(log_file, true);
    file->set_level(spdlog::level::debug);
    sinks.push_back(file);
  }
  auto logger = std::make_shared<spdlog::logger>("shatter", sinks.begin(), sinks.end());
  logger->set_level(spdlog::level::debug);
  logger->set_pattern(world.distributed()
                          ? fmt::format("[%H:%M:%S] [rank {}] %^%l%$ %v", world.rank())
                          : std::string("[%H:%M:%S] %^%l%$ %v"));
  spdlog::set_default_logger(logger);
}

// " (did you mean 'run'?)" for a misspelt command: the command at the smallest edit distance,
// counting a swap of two letters as one edit (rnu, chekc), within 2 edits or a third of the word.
std::string nearest_command(const std::string& word, const std::vector<std::string>& names) {
  std::string best;
  std::size_t best_d = std::max<std::size_t>(2, word.size() / 3) + 1;
  for (const auto& n : names) {
    std::size_t d = shatter::io::edit_distance(word, n);
    std::string a = word, b = n;
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    if (a == b) d = std::min<std::size_t>(d, 1);
    if (d < best_d) {
      best_d = d;
      best = n;
    }
  }
  return best.empty() ? std::string{} : fmt::format(" (did you mean '{}'?)", best);
}

// The command line: every subcommand with the values CLI11 fills as it parses, and the call each
// subcommand makes once parsed. An option that only matters when given fills a std::optional, so
// the command's own default stays the one in its options struct.
struct CommandLine {
  CLI::App app{"shatter: MPM shock physics for hypervelocity impacts on rock and asteroids"};
  bool quiet = false;
  std::string log_file;
  shatter::cli::RunOptions run_options;
  std::string out_dir;

  CLI::App* run = nullptr;
  std::string scene_file;
  CLI::App* check = nullptr;
  std::string check_file;
  CLI::App* reference = nullptr;
  std::vector<std::string> reference_roots;
  std::optional<std::filesystem::path> reference_write;
  CLI::App* resume = nullptr;
  std::string checkpoint;

  CLI::App* fragments = nullptr;
  std::string snapshot;
  shatter::cli::FragmentOptions fragment_options;

  CLI::App* material = nullptr;
  shatter::cli::MaterialOptions material_options;

  CommandLine() {
    app.set_version_flag("--version", std::string("shatter ") + SHATTER_VERSION);
    app.require_subcommand(1);
    add_run();
    add_check();
    add_reference();
    add_resume();
    add_fragments();
    add_material();
  }

  // The flags run and resume share.
  void add_run_flags(CLI::App* cmd) {
    cmd->add_option("--out", out_dir, "run directory (default: the scene's output.directory)");
    // Bounded: oneTBB crashes on an arena of a billion threads (found by tests/fuzz).
    cmd->add_option("--threads", run_options.threads,
                    "worker threads (0 = all cores, at most 4096)")
        ->check(CLI::Range(0, 4096));
    cmd->add_option("--set", run_options.sets, "override a scene key: dotted.key=value")
        ->take_all();
    cmd->add_flag("--quiet", quiet, "only warnings and errors");
    cmd->add_option("--log", log_file, "also write the log to this file");
    cmd->add_flag("--take-lock", run_options.take_lock,
                  "take over the run directory's lock left by a run on another host that ended");
  }

  void add_run() {
    run = app.add_subcommand("run", "run a scene");
    run->add_option("SCENE", scene_file, "scene file (TOML)")->required();
    run->add_flag("--overwrite", run_options.overwrite, "replace a previous run in the directory");
    run->add_flag(
        "--check", run_options.check,
        "check the scene and set the run up (points, materials), then stop; writes nothing");
    add_run_flags(run);
  }

  void add_check() {
    check = app.add_subcommand(
        "check", "validate a scene and estimate its points, memory, steps and run time (no run)");
    check->add_option("SCENE", check_file, "scene file (TOML)")->required();
    check->add_option("--threads", run_options.threads, "threads the run-time estimate assumes")
        ->check(CLI::Range(0, 4096));
    check->add_option("--set", run_options.sets, "override a scene key: dotted.key=value")
        ->take_all();
    check->add_flag("--quiet", quiet, "only warnings and errors");
    check->add_flag("--stages", run_options.stages,
                    "also print the step's stage list as the scene builds it (transfer, filters, "
                    "outflow, MPI exchanges); creates the particles, as run --check does");
  }

  void add_reference() {
    reference = app.add_subcommand(
        "scene-reference", "print the scene key reference (docs/scenes.md) from the scene reader");
    reference->add_option("SCENES", reference_roots,
                          "scene files or folders read to record the keys (default: scenes)");
    reference->add_option("--write", reference_write,
                          "replace the generated section of this file (docs/scenes.md)");
  }

  void add_resume() {
    resume = app.add_subcommand("resume", "continue a run from its checkpoint");
    resume->add_option("CHECKPOINT", checkpoint, "checkpoint file (run directory/checkpoint.h5)")
        ->required();
    add_run_flags(resume);
    resume->add_flag("--accept-timeseries-gap", run_options.accept_timeseries_gap,
                     "continue a timeseries.csv that lost rows the checkpoint covers (deleted, "
                     "emptied or truncated), leaving the gap");
  }

  void add_fragments() {
    fragments = app.add_subcommand("fragments", "find fragments in a snapshot");
    fragments->add_option("SNAPSHOT", snapshot, "snapshot file (HDF5)")->required();
    fragments->add_option("--threshold", fragment_options.threshold,
                          "damage at which a point has failed");
    fragments->add_option("--method", fragment_options.method, "grid_density | friends_of_friends");
    fragments->add_option("--prefix", fragment_options.prefix, "output files PREFIX.csv/.h5/.ss");
    fragments->add_option(
        "--smoothing-factor", fragment_options.smoothing_factor,
        "friends_of_friends: friends within one SPH smoothing length h = F (m/rho)^(1/3) (BA95)");
    fragments->add_option(
        "--static-strength", fragment_options.static_strength,
        "friends_of_friends: undamaged points at this principal tension (Pa) count as failed");
    fragments->add_flag("--ss-particles", fragment_options.ss_particles,
                        "also PREFIX_particles.ss: every point, for reaccumulation");
    fragments->add_option("--ss-radius", fragment_options.ss_radius,
                          "radius of the .ss records: equal_volume (default) | packing_safe");
    fragments->add_flag("--quiet", quiet, "only warnings and errors");
  }

  void add_material() {
    auto& o = material_options;
    material = app.add_subcommand(
        "material",
        "probe a catalogue material: EOS states at (rho, E) and its principal Hugoniot");
    material->add_option("NAME", o.name, "catalogue material (see --list)");
    material->add_flag("--list", o.list, "list the catalogue materials and sources");
    material->add_option("--rho", o.rho, "densities, kg/m^3: R1,R2,...");
    material->add_option("--energy", o.energy, "specific energies, J/kg: E1,E2,...");
    material->add_option("--rho-sweep", o.rho_sweep, "densities MIN:MAX:N");
    material->add_option("--energy-sweep", o.energy_sweep, "energies MIN:MAX:N");
    material->add_option("--hugoniot", o.up_max,
                         "principal Hugoniot for particle speeds 0..UP_MAX m/s");
    material->add_option("--points", o.points, "rows of --hugoniot (default 11)");
    material->add_option("--up", o.up, "Hugoniot at these particle speeds, m/s");
    material->add_option("--ref-rho", o.ref_rho, "Hugoniot reference density (default rho0)");
    material->add_option("--ref-energy", o.ref_energy, "Hugoniot reference energy (default 0)");
    material->add_option("--param", o.params, "override a parameter: KEY=VALUE")->take_all();
    material->add_flag("--csv", o.csv, "CSV (units in the header) instead of a table");
    material->add_option("--out", o.out, "write to this file instead of stdout");
    material->add_option("--catalogue", o.catalogue, "catalogue file (TOML)");
    material->add_flag("--quiet", quiet, "only warnings and errors");
  }

  // A misspelt command gets the nearest one (CLI11 would only say that one is required).
  bool refuse_unknown_command(int argc, char** argv) {
    if (argc <= 1 || argv[1][0] == '-') return false;
    std::vector<std::string> names;
    for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) {
      names.push_back(sub->get_name());
    }
    if (std::find(names.begin(), names.end(), argv[1]) != names.end()) return false;
    fmt::print(stderr, "unknown command '{}'{} (commands: {}; shatter --help describes them)\n",
               argv[1], nearest_command(argv[1], names), fmt::join(names, ", "));
    return true;
  }

  // Only run, resume and check --stages take part in an MPI run.
  bool refuse_on_several_ranks() const {
    const auto& world = shatter::parallel::world();
    const bool stage_list = check->parsed() && run_options.stages;
    if (!world.distributed() || run->parsed() || resume->parsed() || stage_list) return false;
    if (world.rank() == 0) {
      spdlog::error(
          "only 'run', 'resume' and 'check --stages' run on several MPI ranks; start the others "
          "alone");
    }
    return true;
  }

  // Runs the parsed subcommand.
  int dispatch() {
    using namespace shatter::cli;
    if (run->parsed()) return run_command(scene_file, run_options);
    if (resume->parsed()) return resume_command(checkpoint, run_options);
    if (check->parsed()) return check_command(check_file, run_options);
    if (reference->parsed()) {
      return reference_command({reference_roots.begin(), reference_roots.end()}, reference_write);
    }
    if (fragments->parsed()) return fragments_command(snapshot, fragment_options);
    if (material->parsed()) return material_command(material_options);
    return kOk;
  }
};

}  // namespace

int shatter_main(int argc, char** argv) {
  using namespace shatter::cli;
  CommandLine cli;
  if (cli.refuse_unknown_command(argc, argv)) return kBadInput;
  try {
    cli.app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return cli.app.exit(e) == 0 ? kOk : kBadInput;
  }
  setup_logging(cli.quiet, cli.log_file);
  if (!cli.out_dir.empty()) cli.run_options.out = cli.out_dir;
  if (cli.refuse_on_several_ranks()) return kBadInput;
  const auto& world = shatter::parallel::world();
  try {
    return cli.dispatch();
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    // One rank failed alone: it reports (the log line names the rank) and ends every rank,
    // none left waiting in a collective for it.
    if (world.distributed()) world.abort(kFailure);
    return kFailure;
  }
}

int main(int argc, char** argv) {
  shatter::io::skip_hdf5_shutdown_at_exit();
  shatter::parallel::init(&argc, &argv);
  const int code = shatter_main(argc, argv);
  shatter::parallel::finalize();
  return code;
}
