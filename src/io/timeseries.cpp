#include "shatter/io/timeseries.hpp"

#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

namespace shatter::io {
namespace {

constexpr std::string_view kHeader =
    "step,time_s,dt_s,kinetic_J,internal_J,potential_J,total_J,boundary_work_J,outflow_J,"
    "energy_error,px_kg_m_per_s,py_kg_m_per_s,pz_kg_m_per_s,failure_ratio,wall_s";

std::ofstream open_for_writing(const std::filesystem::path& file, std::ios::openmode mode) {
  std::ofstream out(file, mode);
  if (!out) throw std::runtime_error(fmt::format("cannot write {}", file.string()));
  return out;
}

}  // namespace

std::string_view timeseries_header() {
  return kHeader;
}

TimeSeriesWriter::TimeSeriesWriter(const std::filesystem::path& file)
    : out_(open_for_writing(file, std::ios::trunc)) {
  out_ << kHeader << '\n';
}

TimeSeriesWriter::TimeSeriesWriter(const std::filesystem::path& file, double resume_after) {
  std::vector<std::string> keep;
  if (std::ifstream in(file); in) {
    std::string line;
    std::getline(in, line);  // header
    while (std::getline(in, line)) {
      const auto a = line.find(',');
      if (a == std::string::npos) break;
      const auto b = line.find(',', a + 1);
      double t = 0.0;
      try {
        t = std::stod(line.substr(a + 1, b - a - 1));
      } catch (const std::exception&) {
        break;  // a torn last line from a crash: drop it and what follows
      }
      if (t > resume_after) break;
      keep.push_back(line);
    }
  }
  out_ = open_for_writing(file, std::ios::trunc);
  out_ << kHeader << '\n';
  for (const auto& l : keep) out_ << l << '\n';
}

void TimeSeriesWriter::write(const TimeSeriesRow& r) {
  const EnergyBudget& e = r.energy;
  out_ << fmt::format(
      "{},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.9g},"
      "{:.17g},{:.17g},{:.17g},{:.9g},{:.3f}\n",
      r.step, r.time, r.dt, e.kinetic, e.internal, e.potential, e.total(), e.boundary_work,
      e.outflow, e.error(), r.momentum.x(), r.momentum.y(), r.momentum.z(), r.failure_ratio,
      r.wall);
}

Eigen::Vector3d total_momentum(const ParticleStore& store) {
  const auto m = store.col(Field::mass);
  const auto vx = store.col(Field::vx);
  const auto vy = store.col(Field::vy);
  const auto vz = store.col(Field::vz);
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < store.size(); ++i) {
    p += m[i] * Eigen::Vector3d(vx[i], vy[i], vz[i]);
  }
  return p;
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

}  // namespace shatter::io
