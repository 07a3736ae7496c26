#include "shatter/io/timeseries.hpp"

#include <algorithm>
#include <charconv>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "shatter/io/atomic_file.hpp"

namespace shatter::io {
namespace {

constexpr std::string_view kHeader =
    "step,time_s,dt_s,kinetic_J,internal_J,potential_J,total_J,boundary_work_J,outflow_J,"
    "energy_error,px_kg_m_per_s,py_kg_m_per_s,pz_kg_m_per_s,failure_ratio,unresolved_kinetic_J,"
    "unresolved_kinetic_fraction,gravitational_J,";

std::ofstream open_for_writing(const std::filesystem::path& file, std::ios::openmode mode) {
  std::ofstream out(file, mode);
  if (!out) throw std::runtime_error(fmt::format("cannot write {}", file.string()));
  return out;
}

}  // namespace

// The beta columns (issue 32; docs/validation-dart.md).
constexpr std::string_view kBetaHeader =
    "ejecta_mass_kg,ejecta_momentum_kg_m_per_s,impactor_momentum_kg_m_per_s,beta,beta_target,"
    "beta_launch,";

std::string timeseries_header(bool porous, bool beta) {
  return std::string(kHeader) + (porous ? "mean_porosity,compaction_J," : "") +
         (beta ? std::string(kBetaHeader) : std::string()) + "wall_s";
}

TimeSeriesWriter::TimeSeriesWriter(const std::filesystem::path& file, bool porous, bool beta)
    : file_(file),
      porous_(porous),
      beta_(beta),
      header_(timeseries_header(porous, beta)),
      out_(open_for_writing(file, std::ios::trunc)) {
  out_ << header_ << '\n';
}

namespace {

// Byte length of the complete rows (newline-terminated, every column, a step number) with
// steps up to and including `through`, after the header; and the last such row's step.
std::pair<std::size_t, std::optional<std::uint64_t>> rows_through(const std::string& text,
                                                                  const std::string& header,
                                                                  std::uint64_t through) {
  const auto columns = static_cast<std::size_t>(std::count(header.begin(), header.end(), ','));
  const std::size_t from = header.size() + 1;
  std::size_t keep = from;
  std::optional<std::uint64_t> last;
  for (std::size_t pos = keep; pos < text.size();) {
    const auto nl = text.find('\n', pos);
    if (nl == std::string::npos) break;
    const std::string_view line(text.data() + pos, nl - pos);
    if (static_cast<std::size_t>(std::count(line.begin(), line.end(), ',')) != columns) break;
    std::uint64_t step = 0;
    const auto comma = line.find(',');
    const auto [end, ec] = std::from_chars(line.data(), line.data() + comma, step);
    if (ec != std::errc() || end != line.data() + comma || step > through) break;
    last = step;
    keep = nl + 1;
    pos = nl + 1;
  }
  return {keep, last};
}

}  // namespace

TimeSeriesWriter::TimeSeriesWriter(const std::filesystem::path& file, const ResumeRows& resume,
                                   bool porous, bool beta)
    : file_(file), porous_(porous), beta_(beta), header_(timeseries_header(porous, beta)) {
  std::string text;
  if (std::ifstream in(file, std::ios::binary); in) {
    std::stringstream ss;
    ss << in.rdbuf();
    text = ss.str();
  }
  const std::string header = header_ + '\n';
  const bool has_header = text.rfind(header, 0) == 0;
  if (!has_header && header.rfind(text, 0) != 0) {
    // Not this program's time series (another header): refuse rather than destroy its rows.
    throw std::runtime_error(fmt::format(
        "{} does not start with the time-series header of this shatter; move it away to resume",
        file.string()));
  }
  // Keep complete rows up to and including the checkpoint's last row; cut the file after it. A
  // row the dead run wrote after that, or tore while writing, goes; the resumed run writes it
  // again, byte for byte.
  const auto [keep, last] =
      has_header ? rows_through(text, header_, resume.through_step)
                 : std::pair<std::size_t, std::optional<std::uint64_t>>{0, std::nullopt};
  if (last != resume.through_step) {
    const std::string lost =
        fmt::format("{} {}, the checkpoint covers rows to step {}", file.string(),
                    last ? fmt::format("ends at step {}", *last)
                         : std::string(text.empty() ? "is missing or empty" : "has no rows"),
                    resume.through_step);
    if (!resume.accept_gap) {
      throw TimeSeriesGap(lost +
                          ": its earlier rows are lost (restore the file, or pass "
                          "--accept-timeseries-gap to continue it with the gap)");
    }
    note_ = lost + ": continuing it with those rows missing";
  }
  if (!has_header) {
    // Missing, or torn before the header was complete: start it again.
    out_ = open_for_writing(file, std::ios::trunc);
    out_ << header;
    sync();
    return;
  }
  if (keep < text.size()) {
    // Cut in place (one truncate), never rewritten: a crash here loses no kept row.
    std::error_code ec;
    std::filesystem::resize_file(file, keep, ec);
    if (ec) {
      throw std::runtime_error(
          fmt::format("cannot truncate {} for the resume: {}", file.string(), ec.message()));
    }
  }
  out_ = open_for_writing(file, std::ios::app);
  sync();
}

void TimeSeriesWriter::flush() {
  out_.flush();
  if (!out_) throw std::runtime_error(fmt::format("error writing {}", file_.string()));
}

void TimeSeriesWriter::sync() {
  flush();
  sync_file(file_);
}

void TimeSeriesWriter::write(const TimeSeriesRow& r) {
  const EnergyBudget& e = r.energy;
  out_ << fmt::format(
      "{},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.9g},"
      "{:.17g},{:.17g},{:.17g},{:.9g},{:.17g},{:.9g},{:.17g},",
      r.step, r.time, r.dt, e.kinetic, e.internal, e.potential, e.total(), e.boundary_work,
      e.outflow, e.error(), r.momentum.x(), r.momentum.y(), r.momentum.z(), r.failure_ratio,
      e.unresolved_kinetic, e.unresolved_fraction(), e.gravitational);
  if (porous_) out_ << fmt::format("{:.17g},{:.17g},", r.mean_porosity, r.compaction_work);
  if (beta_) {
    out_ << fmt::format("{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},", r.ejecta_mass,
                        r.ejecta_momentum, r.impactor_momentum, r.beta, r.beta_target,
                        r.beta_launch);
  }
  out_ << fmt::format("{:.3f}\n", r.wall);
}

std::array<parallel::ExactSum, 3> porosity_sums(const ParticleStore& store) {
  std::array<parallel::ExactSum, 3> s;
  if (!store.has(Field::distension)) return s;
  const auto m = store.col(Field::mass);
  const auto alpha = store.col(Field::distension);
  // a store without the column (made by hand, not by a porous material): no compaction work
  const double* q =
      store.has(Field::compaction_heat) ? store.col(Field::compaction_heat).data() : nullptr;
  for (std::size_t i = 0; i < store.size(); ++i) {
    if (!(alpha[i] >= 1.0)) continue;  // a point of a dense material
    s[0].add(m[i] * (1.0 - 1.0 / alpha[i]));
    s[1].add(m[i]);
    if (q != nullptr) s[2].add(m[i] * q[i]);
  }
  return s;
}

double mean_porosity(std::array<parallel::ExactSum, 3>& sums) {
  const double mass = sums[1].value();
  return mass > 0.0 ? sums[0].value() / mass : 0.0;
}

double mean_porosity(const ParticleStore& store) {
  auto s = porosity_sums(store);
  return mean_porosity(s);
}

std::array<parallel::ExactSum, 3> momentum_sums(const ParticleStore& store) {
  const auto m = store.col(Field::mass);
  const auto vx = store.col(Field::vx);
  const auto vy = store.col(Field::vy);
  const auto vz = store.col(Field::vz);
  std::array<parallel::ExactSum, 3> p;
  for (std::size_t i = 0; i < store.size(); ++i) {
    p[0].add(m[i] * vx[i]);
    p[1].add(m[i] * vy[i]);
    p[2].add(m[i] * vz[i]);
  }
  return p;
}

Eigen::Vector3d total_momentum(const ParticleStore& store) {
  auto p = momentum_sums(store);
  return {p[0].value(), p[1].value(), p[2].value()};
}

std::array<std::int64_t, 2> failure_counts(const ParticleStore& store, double threshold,
                                           const std::vector<bool>& counted) {
  std::array<std::int64_t, 2> c{0, 0};
  if (!store.has(Field::damage)) return c;
  const auto d = store.col(Field::damage);
  const auto& groups = store.groups();
  for (std::size_t g = 0; g < groups.size(); ++g) {
    if (g >= counted.size() || !counted[g]) continue;
    for (std::size_t p = groups[g].range.begin; p < groups[g].range.end; ++p) {
      c[0] += d[p] >= threshold ? 1 : 0;
    }
    c[1] += static_cast<std::int64_t>(groups[g].range.size());
  }
  return c;
}

double failure_ratio(const ParticleStore& store, double threshold,
                     const std::vector<bool>& counted) {
  if (!store.has(Field::damage)) return 0.0;
  const auto d = store.col(Field::damage);
  std::size_t failed = 0, total = 0;
  const auto& groups = store.groups();
  for (std::size_t g = 0; g < groups.size(); ++g) {
    if (g >= counted.size() || !counted[g]) continue;
    for (std::size_t p = groups[g].range.begin; p < groups[g].range.end; ++p) {
      failed += d[p] >= threshold ? 1 : 0;
    }
    total += groups[g].range.size();
  }
  return total == 0 ? 0.0 : static_cast<double>(failed) / static_cast<double>(total);
}

double failed_mass_fraction(const ParticleStore& store, double threshold,
                            const std::vector<bool>& counted) {
  if (!store.has(Field::damage)) return 0.0;
  const auto d = store.col(Field::damage);
  const auto m = store.col(Field::mass);
  parallel::ExactSum failed, total;  // exact: the same bits in any point order
  const auto& groups = store.groups();
  for (std::size_t g = 0; g < groups.size(); ++g) {
    if (g >= counted.size() || !counted[g]) continue;
    for (std::size_t p = groups[g].range.begin; p < groups[g].range.end; ++p) {
      if (d[p] >= threshold) failed.add(m[p]);
      total.add(m[p]);
    }
  }
  const double all = total.value();
  return all > 0.0 ? failed.value() / all : 0.0;
}

}  // namespace shatter::io
