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
  std::vector<std::string> sets;             // --set key=value
};

int run_command(const std::filesystem::path& scene_file, const RunOptions& options);
int resume_command(const std::filesystem::path& checkpoint, const RunOptions& options);

struct FragmentOptions {
  std::optional<double> threshold;
  std::optional<std::string> method;
  std::optional<std::filesystem::path> prefix;  // output files: PREFIX.csv, .h5, .pkdgrav
};
int fragments_command(const std::filesystem::path& snapshot, const FragmentOptions& options);

}  // namespace shatter::cli
