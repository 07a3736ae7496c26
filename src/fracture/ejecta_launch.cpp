// The ejecta's launch record (include/shatter/fracture/ejecta_launch.hpp).

#include "shatter/fracture/ejecta_launch.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "point_motion.hpp"

namespace shatter {
namespace {

constexpr std::string_view kHeader =
    "id,launch_time_s,mass_kg,speed_m_per_s,normal_speed_m_per_s,back_speed_m_per_s,"
    "launch_radius_m,launch_height_m,cumulative_mass_kg";

}  // namespace

void EjectaLaunches::record(const ParticleStore& store, const BetaSpec& spec, double time) {
  BetaSpec any_speed = spec;
  any_speed.escape_speed = 0.0;  // the whole launch distribution; a reader cuts at v_esc
  const fracture::PointMotion pts(store);
  const auto id = store.col(IField::id);
  for (std::size_t p = 0; p < store.size(); ++p) {
    const Eigen::Vector3d xp = pts.position(p);
    const Eigen::Vector3d vp = pts.velocity(p);
    if (!is_ejecta(any_speed, xp, vp) || launches_.count(id[p]) != 0) continue;
    const Eigen::Vector3d rel = xp - spec.surface_point;
    const double h = rel.dot(spec.normal);
    launches_[id[p]] = {time,
                        pts.mass[p],
                        vp.norm(),
                        vp.dot(spec.normal),
                        -vp.dot(spec.direction),
                        (rel - h * spec.normal).norm(),
                        h};
  }
}

std::string EjectaLaunches::csv() const {
  std::vector<std::pair<std::int64_t, EjectaLaunch>> rows(launches_.begin(), launches_.end());
  // Fastest first (ties by id, so the file is the same in any order of recording).
  std::sort(rows.begin(), rows.end(), [](const auto& a, const auto& b) {
    return a.second.speed != b.second.speed ? a.second.speed > b.second.speed : a.first < b.first;
  });
  std::string out = fmt::format("# impactor_mass_kg={:.17g} impact_speed_m_per_s={:.17g}\n{}\n",
                                impactor_mass_, impact_speed_, kHeader);
  double cumulative = 0.0;  // M(>= v): Housen & Holsapple 2011's cumulative ejecta mass
  for (const auto& [i, l] : rows) {
    cumulative += l.mass;
    out += fmt::format("{},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}\n", i,
                       l.time, l.mass, l.speed, l.normal_speed, l.back_speed, l.radius, l.height,
                       cumulative);
  }
  return out;
}

double EjectaLaunches::beta_at_launch(double escape_speed) const {
  const double p_imp = impactor_mass_ * impact_speed_;
  if (!(p_imp > 0.0)) return 1.0;
  double p_ej = 0.0;
  for (const auto& [i, l] : launches_) {
    if (l.speed >= escape_speed) p_ej += l.mass * l.back_speed;
  }
  return 1.0 + p_ej / p_imp;  // Cheng et al. 2023, Eq. 1
}

void EjectaLaunches::read(std::string_view text, const std::string& source, double through_time) {
  std::istringstream in{std::string(text)};
  std::string line;
  int n = 0;
  bool header = false;
  while (std::getline(in, line)) {
    ++n;
    if (line.empty()) continue;
    if (line[0] == '#') {
      std::sscanf(line.c_str(), "# impactor_mass_kg=%lf impact_speed_m_per_s=%lf", &impactor_mass_,
                  &impact_speed_);
      continue;
    }
    if (!header) {
      if (line != kHeader) {
        throw std::runtime_error(fmt::format("{}:{}: not an ejecta launch table", source, n));
      }
      header = true;
      continue;
    }
    std::istringstream row(line);
    std::string cell;
    std::vector<double> v;
    std::int64_t id = 0;
    for (int c = 0; std::getline(row, cell, ','); ++c) {
      char* end = nullptr;
      if (c == 0) {
        id = std::strtoll(cell.c_str(), &end, 10);
      } else {
        v.push_back(std::strtod(cell.c_str(), &end));
      }
      if (end == cell.c_str() || *end != '\0') {
        throw std::runtime_error(fmt::format("{}:{}: bad value '{}'", source, n, cell));
      }
    }
    if (v.size() != 8) throw std::runtime_error(fmt::format("{}:{}: needs 9 columns", source, n));
    if (v[0] <= through_time) launches_[id] = {v[0], v[1], v[2], v[3], v[4], v[5], v[6]};
  }
  if (!header) throw std::runtime_error(fmt::format("{}: no ejecta launch table", source));
}

}  // namespace shatter
