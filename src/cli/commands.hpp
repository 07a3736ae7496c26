#pragma once
// The `shatter` subcommands. Each returns the process exit status (see ExitCode).

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace shatter::cli {

enum ExitCode : int {
  kOk = 0,
  kFailure = 1,    // unexpected error (I/O, internal)
  kBadInput = 2,   // scene, command line or input file refused
  kNumerical = 3,  // the state stopped being finite or the time step collapsed
};

struct RunOptions {
  std::optional<std::filesystem::path> out;  // run directory (default: the scene's)
  int threads = 0;                           // 0 = all cores
  bool overwrite = false;                    // replace a previous run in the directory
  bool check = false;  // run: check the scene and set the run up, then stop (nothing written)
  std::vector<std::string> sets;  // --set key=value
};

int run_command(const std::filesystem::path& scene_file, const RunOptions& options);
int resume_command(const std::filesystem::path& checkpoint, const RunOptions& options);

struct FragmentOptions {
  std::optional<double> threshold;
  std::optional<std::string> method;
  std::optional<std::filesystem::path> prefix;  // output files: PREFIX.csv, .h5, .ss
  bool ss_particles = false;                    // also PREFIX_particles.ss (every point)
};
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
