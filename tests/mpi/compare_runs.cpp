// compare_runs A B: compares two run directories (or two checkpoint files) bit for bit.
//
// The particles of the checkpoints (every column both hold: positions, velocities, stress,
// damage, flaws, ids, ...) are matched by particle id, since a single process writes its store
// order and a run on several ranks writes rows sorted by id; the clock, the energy accounts
// and internal_next must be equal too, and for run directories the rows of timeseries.csv
// (all but the wall-clock column). Tolerance: zero, every bit (docs/mpi.md). Exit 0 when
// equal, 1 with the first difference.

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "shatter/io/checkpoint.hpp"

namespace fs = std::filesystem;
using namespace shatter;

namespace {

std::vector<std::size_t> id_order(const ParticleStore& P) {
  std::vector<std::size_t> o(P.size());
  std::iota(o.begin(), o.end(), std::size_t{0});
  const auto id = P.col(IField::id);
  std::sort(o.begin(), o.end(), [&](std::size_t a, std::size_t b) { return id[a] < id[b]; });
  return o;
}

// Which columns take part: all (strict), all but the named ones, or those both files hold.
struct ColumnFilter {
  std::vector<std::string> ignored;
  bool common_only = false;

  bool ignores(std::string_view name) const {
    return std::find(ignored.begin(), ignored.end(), name) != ignored.end();
  }
  // "" when the column is compared (both hold it), else why not, or an error.
  template <class F>
  std::string skip(const ParticleStore& a, const ParticleStore& b, F f, bool& error) const {
    error = false;
    if (ignores(name_of(f))) return "ignored";
    if (a.has(f) == b.has(f)) return a.has(f) ? "" : "absent";
    error = !common_only;
    return fmt::format("column {} in {} only", name_of(f), a.has(f) ? "A" : "B");
  }
};

bool known_column(std::string_view name) {
  for (std::size_t i = 0; i < kIFieldCount; ++i) {
    if (name_of(static_cast<IField>(i)) == name) return true;
  }
  for (std::size_t i = 0; i < kFieldCount; ++i) {
    if (name_of(static_cast<Field>(i)) == name) return true;
  }
  return false;
}

// Lists (once) the columns one file holds and the other does not, under --common-columns.
std::string one_file_columns(const ParticleStore& a, const ParticleStore& b) {
  std::string out;
  auto add = [&](std::string_view name, bool in_a) {
    out += fmt::format("{}{} ({})", out.empty() ? "" : ", ", name, in_a ? "A" : "B");
  };
  for (std::size_t i = 0; i < kIFieldCount; ++i) {
    const auto f = static_cast<IField>(i);
    if (a.has(f) != b.has(f)) add(name_of(f), a.has(f));
  }
  for (std::size_t i = 0; i < kFieldCount; ++i) {
    const auto f = static_cast<Field>(i);
    if (a.has(f) != b.has(f)) add(name_of(f), a.has(f));
  }
  return out;
}

std::string compare_stores(const ParticleStore& a, const ParticleStore& b,
                           const ColumnFilter& filter) {
  if (a.size() != b.size()) return fmt::format("{} vs {} particles", a.size(), b.size());
  if (a.size() == 0) return "no particles";
  const auto oa = id_order(a), ob = id_order(b);
  bool error = false;
  for (std::size_t i = 0; i < kIFieldCount; ++i) {
    const auto f = static_cast<IField>(i);
    const auto why = filter.skip(a, b, f, error);
    if (error) return why;
    if (!why.empty()) continue;
    for (std::size_t k = 0; k < oa.size(); ++k) {
      if (a.col(f)[oa[k]] != b.col(f)[ob[k]]) {
        return fmt::format("{}: row {} (by id) {} vs {}", name_of(f), k, a.col(f)[oa[k]],
                           b.col(f)[ob[k]]);
      }
    }
  }
  for (std::size_t i = 0; i < kFieldCount; ++i) {
    const auto f = static_cast<Field>(i);
    const auto why = filter.skip(a, b, f, error);
    if (error) return why;
    if (!why.empty()) continue;
    std::size_t bad = 0, first = 0;
    for (std::size_t k = 0; k < oa.size(); ++k) {
      if (std::bit_cast<std::uint64_t>(a.col(f)[oa[k]]) !=
          std::bit_cast<std::uint64_t>(b.col(f)[ob[k]])) {
        if (bad++ == 0) first = k;
      }
    }
    if (bad > 0) {
      return fmt::format("{}: {} of {} particles differ; first id {}: {:.17g} vs {:.17g}",
                         name_of(f), bad, oa.size(), a.col(IField::id)[oa[first]],
                         a.col(f)[oa[first]], b.col(f)[ob[first]]);
    }
  }
  return {};
}

bool same_bits(double x, double y) {
  return std::bit_cast<std::uint64_t>(x) == std::bit_cast<std::uint64_t>(y);
}

std::string compare_state(const io::RunState& a, const io::RunState& b) {
  const std::pair<const char*, std::pair<double, double>> v[] = {
      {"time", {a.clock.time, b.clock.time}},
      {"dt", {a.clock.dt, b.clock.dt}},
      {"kinetic", {a.energy.kinetic, b.energy.kinetic}},
      {"internal", {a.energy.internal, b.energy.internal}},
      {"potential", {a.energy.potential, b.energy.potential}},
      {"boundary_work", {a.energy.boundary_work, b.energy.boundary_work}},
      {"outflow", {a.energy.outflow, b.energy.outflow}},
      {"internal_next", {a.internal_next, b.internal_next}}};
  if (a.clock.step != b.clock.step) return fmt::format("step {} vs {}", a.clock.step, b.clock.step);
  for (const auto& [name, xy] : v) {
    if (!same_bits(xy.first, xy.second)) {
      return fmt::format("{}: {:.17g} vs {:.17g}", name, xy.first, xy.second);
    }
  }
  return {};
}

std::vector<std::string> rows(const fs::path& p) {
  std::ifstream in(p);
  std::vector<std::string> out;
  for (std::string line; std::getline(in, line);) {
    const auto cut = line.rfind(',');
    out.push_back(cut == std::string::npos ? line : line.substr(0, cut));
  }
  return out;
}

// --report: how far apart two runs are, per column (max |a - b| over max |a|), for runs that
// are not meant to be bitwise equal (docs/mpi.md: the canonical block order against the
// previous build).
void report(const ParticleStore& a, const ParticleStore& b) {
  const auto oa = id_order(a), ob = id_order(b);
  for (const Field f : {Field::x, Field::y, Field::z, Field::vx, Field::vy, Field::vz, Field::rho,
                        Field::energy, Field::damage}) {
    if (!a.has(f) || !b.has(f)) continue;
    double diff = 0.0, scale = 0.0;
    for (std::size_t k = 0; k < oa.size(); ++k) {
      diff = std::max(diff, std::abs(a.col(f)[oa[k]] - b.col(f)[ob[k]]));
      scale = std::max(scale, std::abs(a.col(f)[oa[k]]));
    }
    fmt::print("  {:8s} max |a-b| {:.3e}  max |a| {:.3e}  relative {:.2e}\n", name_of(f), diff,
               scale, scale > 0 ? diff / scale : 0.0);
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> paths;
  bool want_report = false;
  ColumnFilter filter;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--report") {
      want_report = true;
    } else if (arg == "--common-columns") {
      filter.common_only = true;
    } else if (arg == "--ignore-column" && i + 1 < argc) {
      filter.ignored.emplace_back(argv[++i]);
    } else if (arg.starts_with("--")) {
      paths.clear();
      break;
    } else {
      paths.push_back(arg);
    }
  }
  for (const auto& name : filter.ignored) {
    if (!known_column(name)) {
      fmt::print(stderr, "compare_runs: --ignore-column {}: no such column\n", name);
      return 2;
    }
  }
  if (paths.size() != 2) {
    fmt::print(stderr,
               "usage: compare_runs RUN_A RUN_B [--report] [--ignore-column NAME]... "
               "[--common-columns]\n  (run directories or checkpoints; by default every "
               "column must be held by both)\n");
    return 2;
  }
  const fs::path a = paths[0], b = paths[1];
  const bool dirs = fs::is_directory(a) && fs::is_directory(b);
  try {
    const auto ca = io::read_checkpoint(dirs ? a / "checkpoint.h5" : a);
    const auto cb = io::read_checkpoint(dirs ? b / "checkpoint.h5" : b);
    if (want_report && ca.particles.size() == cb.particles.size()) {
      report(ca.particles, cb.particles);
    }
    std::string err = compare_state(ca.state, cb.state);
    if (err.empty()) err = compare_stores(ca.particles, cb.particles, filter);
    if (err.empty() && dirs) {
      const auto ra = rows(a / "timeseries.csv"), rb = rows(b / "timeseries.csv");
      if (ra.size() != rb.size())
        err = fmt::format("timeseries: {} vs {} rows", ra.size(), rb.size());
      for (std::size_t i = 0; err.empty() && i < ra.size(); ++i) {
        if (ra[i] != rb[i]) err = fmt::format("timeseries row {}: {} vs {}", i, ra[i], rb[i]);
      }
    }
    if (!err.empty()) {
      fmt::print("DIFFERENT {} {}: {}\n", a.string(), b.string(), err);
      return 1;
    }
    const auto skipped = filter.common_only ? one_file_columns(ca.particles, cb.particles) : "";
    fmt::print("bitwise equal: {} {} ({} particles, step {}){}\n", a.string(), b.string(),
               ca.particles.size(), ca.state.clock.step,
               skipped.empty() ? std::string{} : "; not compared, in one file only: " + skipped);
  } catch (const std::exception& e) {
    fmt::print(stderr, "compare_runs: {}\n", e.what());
    return 2;
  }
  return 0;
}
