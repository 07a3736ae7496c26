#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <system_error>
#include <utility>

#include <spdlog/spdlog.h>

#include "commands.hpp"
#include "fragments_report.hpp"
#include "shatter/fracture/fragments.hpp"
#include "shatter/io/snapshot.hpp"

namespace shatter::cli {

namespace {

// An r-z snapshot (issue 31) has the axis as its symmetry face x = 0 and every point on the
// plane y = 0; a 3-D half model's lattice never puts its points there (they sit half a spacing
// off any plane), so this tells the two apart without a new snapshot attribute.
bool rz_snapshot(const io::Snapshot& s, const std::filesystem::path& file) {
  if (s.header.symmetry_axis != 0 || s.particles.size() == 0 || !s.particles.has(Field::y)) {
    return false;
  }
  const auto y = s.particles.col(Field::y);
  if (!std::all_of(y.begin(), y.end(), [](double v) { return v == 0.0; })) return false;
  spdlog::info(
      "{}: an r-z snapshot (axis x = 0, every point on y = 0): rings, searched in the "
      "half-plane",
      file.string());
  return true;
}

}  // namespace

int fragments_command(const std::filesystem::path& snapshot, const FragmentOptions& options) {
  io::Snapshot s;
  try {
    s = io::read_snapshot(snapshot);
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return kBadInput;
  }
  if (!s.header.checksummed) {
    spdlog::warn(
        "{} was written before snapshot headers were checksummed: its time, step and symmetry "
        "axis are not verified (its datasets are)",
        snapshot.string());
  }
  FragmentSearchSpec spec;
  if (options.threshold) {
    if (!(*options.threshold > 0.0 && *options.threshold <= 1.0)) {
      spdlog::error("--threshold must be in (0, 1] (got {})", *options.threshold);
      return kBadInput;
    }
    spec.damage_threshold = *options.threshold;
  }
  if (options.method) spec.method = *options.method;
  for (const auto& [name, value] : {std::pair{"--smoothing-factor", options.smoothing_factor},
                                    std::pair{"--static-strength", options.static_strength}}) {
    if (!value) continue;
    if (spec.method != "friends_of_friends") {
      spdlog::error("{} applies only with --method friends_of_friends", name);
      return kBadInput;
    }
    if (!(*value > 0.0) || !std::isfinite(*value)) {
      spdlog::error("{} must be a positive number (got {})", name, *value);
      return kBadInput;
    }
  }
  if (options.ss_radius) {
    try {
      spec.ss_radius = ss_radius_by_name(*options.ss_radius);
    } catch (const std::invalid_argument& e) {
      spdlog::error("--ss-radius: {}", e.what());
      return kBadInput;
    }
  }
  spec.smoothing_factor = options.smoothing_factor.value_or(0.0);
  spec.axisymmetric = rz_snapshot(s, snapshot);
  spec.static_strength = options.static_strength.value_or(0.0);
  std::filesystem::path prefix =
      options.prefix.value_or(snapshot.parent_path() / (snapshot.stem().string() + "_fragments"));
  // `--prefix post/frag`: the folder is created (said so) rather than failing on the first file.
  if (const auto dir = prefix.parent_path(); !dir.empty() && !std::filesystem::is_directory(dir)) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) {
      spdlog::error("--prefix {}: cannot create the folder {}: {}", prefix.string(), dir.string(),
                    ec.message());
      return kBadInput;
    }
    spdlog::info("created the folder {} for --prefix {}", dir.string(), prefix.string());
  }
  try {
    spdlog::info("{}: t = {} s, step {}, {} points", snapshot.string(), s.header.time,
                 s.header.step, s.particles.size());
    FragmentReportInfo info;
    info.time = s.header.time;
    info.ss_particles = options.ss_particles;
    // Group g is body g and material g (scene/build.cpp); snapshots before names have none.
    if (s.body_names.size() == s.material_names.size()) {
      info.body_names = s.body_names;
      info.body_materials = s.material_names;
    }
    report_fragments(s.particles, s.header.symmetry_axis, spec, prefix, info);
  } catch (const std::logic_error& e) {
    // A snapshot without the columns the search needs, or an unknown method.
    spdlog::error("{}: {}", snapshot.string(), e.what());
    return kBadInput;
  }
  return kOk;
}

}  // namespace shatter::cli
