// Benz & Asphaug 1999's bound remnant (see shatter/fracture/bound_remnant.hpp).

#include "shatter/fracture/bound_remnant.hpp"

#include <fstream>
#include <stdexcept>
#include <string>

#include <fmt/format.h>
#include <Eigen/Dense>

namespace shatter {
namespace {

struct Aggregate {
  double mass = 0.0;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
};

Aggregate aggregate_of(const FragmentCatalogue& cat, const std::vector<bool>& in) {
  Aggregate a;
  Eigen::Vector3d mr = Eigen::Vector3d::Zero(), mv = Eigen::Vector3d::Zero();
  for (std::size_t f = 0; f < cat.fragments.size(); ++f) {
    if (!in[f]) continue;
    const Fragment& F = cat.fragments[f];
    a.mass += F.mass;
    mr += F.mass * F.centre;
    mv += F.mass * F.velocity;
  }
  if (a.mass > 0.0) {
    a.centre = mr / a.mass;
    a.velocity = mv / a.mass;
  }
  return a;
}

// BA99's test: 1/2 m |v - V|^2 < G M m / |r - R| (m cancels).
bool bound_to(const Fragment& F, const Aggregate& a, double G) {
  const double d = (F.centre - a.centre).norm();
  const double v2 = (F.velocity - a.velocity).squaredNorm();
  return d > 0.0 ? 0.5 * v2 * d < G * a.mass : true;
}

// Spin of the aggregate: L and I about its centre of mass (parallel-axis theorem for each
// fragment's own inertia), omega = I^-1 L.
void add_spin(const FragmentCatalogue& cat, BoundRemnant& r) {
  Eigen::Matrix3d I = Eigen::Matrix3d::Zero();
  for (std::int64_t id : r.members) {
    const Fragment& F = cat.fragments[static_cast<std::size_t>(id)];
    const Eigen::Vector3d d = F.centre - r.centre;
    r.angular_momentum += F.angular_momentum + F.mass * d.cross(F.velocity - r.velocity);
    I += F.inertia + F.mass * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
  }
  const Eigen::FullPivLU<Eigen::Matrix3d> lu(I);
  if (lu.isInvertible()) r.omega = lu.solve(r.angular_momentum);
}

}  // namespace

BoundRemnant bound_remnant(const FragmentCatalogue& cat, double G) {
  BoundRemnant r;
  const std::size_t n = cat.fragments.size();
  if (n == 0) return r;
  std::vector<bool> in(n, false);
  in[0] = true;  // the catalogue is sorted by mass: the seed is the largest fragment
  Aggregate a = aggregate_of(cat, in);
  for (bool grew = true; grew;) {
    ++r.iterations;
    grew = false;
    // Every candidate is judged against the same aggregate of this pass, so the result does
    // not depend on the order of the catalogue beyond its seed.
    std::vector<bool> joining(n, false);
    for (std::size_t f = 1; f < n; ++f) {
      if (!in[f] && bound_to(cat.fragments[f], a, G)) joining[f] = grew = true;
    }
    for (std::size_t f = 1; f < n; ++f) in[f] = in[f] || joining[f];
    a = aggregate_of(cat, in);
  }
  r.mass = a.mass;
  r.centre = a.centre;
  r.velocity = a.velocity;
  for (std::size_t f = 0; f < n; ++f) {
    if (in[f]) r.members.push_back(static_cast<std::int64_t>(f));
  }
  add_spin(cat, r);
  return r;
}

void write_bound_remnant_json(const BoundRemnant& r, const FragmentCatalogue& cat,
                              const std::filesystem::path& file) {
  std::ofstream out(file);
  if (!out) throw std::runtime_error(fmt::format("cannot write {}", file.string()));
  const auto vec = [](const Eigen::Vector3d& v) {
    return fmt::format("[{:.17g}, {:.17g}, {:.17g}]", v.x(), v.y(), v.z());
  };
  std::string ids;
  for (std::size_t k = 0; k < r.members.size(); ++k) {
    ids += fmt::format("{}{}", k ? ", " : "", r.members[k]);
  }
  out << fmt::format(
      "{{\n  \"criterion\": \"Benz & Asphaug 1999 iterative energy criterion, fragments as "
      "point masses, dust excluded\",\n  \"mass_kg\": {:.17g},\n  \"mass_fraction\": {:.17g},\n"
      "  \"centre_m\": {},\n  \"velocity_m_per_s\": {},\n  \"speed_m_per_s\": {:.17g},\n"
      "  \"angular_momentum_kg_m2_per_s\": {},\n  \"spin_rad_per_s\": {},\n"
      "  \"spin_rate_rad_per_s\": {:.17g},\n  \"fragments\": [{}],\n  \"passes\": {}\n}}\n",
      r.mass, cat.total_mass > 0.0 ? r.mass / cat.total_mass : 0.0, vec(r.centre), vec(r.velocity),
      r.speed(), vec(r.angular_momentum), vec(r.omega), r.spin(), ids, r.iterations);
  if (!out) throw std::runtime_error(fmt::format("error writing {}", file.string()));
}

}  // namespace shatter
