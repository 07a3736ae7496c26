#pragma once
// The `shatter` subcommands. Each returns the process exit status (see ExitCode).

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace shatter::scene {
struct RunEstimate;
}

namespace shatter::cli {

enum ExitCode : int {
  kOk = 0,
  kFailure = 1,    // unexpected error (I/O, internal)
  kBadInput = 2,   // scene, command line or input file refused
  kNumerical = 3,  // the state stopped being finite or the time step collapsed
  // 128 + N: stopped by signal N (SIGINT 130, SIGTERM 143) after writing a checkpoint
};

struct RunOptions {
  std::optional<std::filesystem::path> out;  // run directory (default: the scene's)
  int threads = 0;                           // 0 = all cores
  bool overwrite = false;                    // replace a previous run in the directory
  bool take_lock = false;  // take over a stale lock that names another host (io::RunLock)
  bool accept_timeseries_gap = false;  // resume: continue a time series that lost rows
  bool check = false;   // run: check the scene and set the run up, then stop (nothing written)
  bool stages = false;  // check: also print the step's stage list (creates the particles)
  std::vector<std::string> sets;  // --set key=value
};

int run_command(const std::filesystem::path& scene_file, const RunOptions& options);
int resume_command(const std::filesystem::path& checkpoint, const RunOptions& options);
// `shatter check`: validates the scene and prints points, memory, steps and run time, without
// creating the particles. Exit 2 when the scene is invalid or larger than the memory available.
int check_command(const std::filesystem::path& scene_file, const RunOptions& options);

struct FragmentOptions {
  std::optional<double> threshold;
  std::optional<std::string> method;
  std::optional<std::filesystem::path> prefix;  // output files: PREFIX.csv, .h5, .ss
  // friends_of_friends (BA95 Sec. 4.4): friends within one SPH smoothing length, h = factor
  // (m/rho)^{1/3} (an SPH run's solver.sph.h_factor); and the static-strength pre-pass, Pa.
  std::optional<double> smoothing_factor;
  std::optional<double> static_strength;
  bool ss_particles = false;             // also PREFIX_particles.ss (every point)
  std::optional<std::string> ss_radius;  // equal_volume | packing_safe (output.ss_radius)
};
// `shatter scene-reference`: the key tables of docs/scenes.md from the scene reader, run over
// the scenes under `roots` (default: scenes/); printed, or written between the markers of the
// file `write`. Exit 2 when an allowed key is read by no example scene.
int reference_command(const std::vector<std::filesystem::path>& roots,
                      const std::optional<std::filesystem::path>& write);

// Why a run of this size cannot fit in the memory available now, or none if it can.
std::optional<std::string> too_large_for_memory(const scene::RunEstimate& e);

int fragments_command(const std::filesystem::path& snapshot, const FragmentOptions& options);

// `shatter material`: the material probe (include/shatter/material/probe.hpp). Lists of numbers
// stay text here so that the command can refuse a malformed one by name.
struct MaterialOptions {
  std::string name;                                // catalogue material
  bool list = false;                               // list the catalogue with sources
  bool csv = false;                                // machine-readable output
  std::optional<std::filesystem::path> out;        // write there instead of stdout
  std::optional<std::filesystem::path> catalogue;  // another catalogue file
  std::vector<std::string> params;                 // KEY=VALUE overrides of the entry
  std::string rho, energy;                         // comma-separated lists (kg/m^3, J/kg)
  std::string rho_sweep, energy_sweep;             // MIN:MAX:N
  std::optional<double> up_max;                    // Hugoniot rows from 0 to up_max (m/s)
  int points = 11;                                 // ... this many
  std::string up;                                  // or an explicit list of up (m/s)
  std::optional<double> ref_rho, ref_energy;       // Hugoniot reference state
};
int material_command(const MaterialOptions& options);

}  // namespace shatter::cli
