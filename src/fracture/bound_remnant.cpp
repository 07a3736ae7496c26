// Benz & Asphaug 1999's bound remnant (see shatter/fracture/bound_remnant.hpp).

#include "shatter/fracture/bound_remnant.hpp"

#include <algorithm>
#include <fstream>
#include <stdexcept>
#include <string>

#include <fmt/format.h>
#include <Eigen/Dense>

namespace shatter {
namespace {

// One body of the criterion: a fragment, or a dust point, as a point mass at its centre.
struct Body {
  double mass = 0.0;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular_momentum = Eigen::Vector3d::Zero();  // own spin (0 for a point)
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();           // own (0 for a point)
};

struct Aggregate {
  double mass = 0.0;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
};

std::vector<Body> fragment_bodies(const FragmentCatalogue& cat) {
  std::vector<Body> b;
  b.reserve(cat.fragments.size());
  for (const Fragment& F : cat.fragments) {
    b.push_back({F.mass, F.centre, F.velocity, F.angular_momentum, F.inertia});
  }
  return b;
}

Aggregate aggregate_of(const std::vector<Body>& bodies, const std::vector<bool>& in) {
  Aggregate a;
  Eigen::Vector3d mr = Eigen::Vector3d::Zero(), mv = Eigen::Vector3d::Zero();
  for (std::size_t f = 0; f < bodies.size(); ++f) {
    if (!in[f]) continue;
    a.mass += bodies[f].mass;
    mr += bodies[f].mass * bodies[f].centre;
    mv += bodies[f].mass * bodies[f].velocity;
  }
  if (a.mass > 0.0) {
    a.centre = mr / a.mass;
    a.velocity = mv / a.mass;
  }
  return a;
}

// BA99's test: 1/2 m |v - V|^2 < G M m / |r - R| (m cancels).
bool bound_to(const Body& F, const Aggregate& a, double G) {
  const double d = (F.centre - a.centre).norm();
  const double v2 = (F.velocity - a.velocity).squaredNorm();
  return d > 0.0 ? 0.5 * v2 * d < G * a.mass : true;
}

// BA99's iteration from the members already in: every body bound to the aggregate joins (all
// judged against the same aggregate in a pass, so the result does not depend on the order of
// the bodies), the aggregate is recomputed, until nothing joins. Returns the passes.
int grow(const std::vector<Body>& bodies, std::vector<bool>& in, double G) {
  int passes = 0;
  for (bool grew = true; grew;) {
    ++passes;
    grew = false;
    const Aggregate a = aggregate_of(bodies, in);
    std::vector<bool> joining(bodies.size(), false);
    for (std::size_t f = 0; f < bodies.size(); ++f) {
      if (!in[f] && bound_to(bodies[f], a, G)) joining[f] = grew = true;
    }
    for (std::size_t f = 0; f < bodies.size(); ++f) in[f] = in[f] || joining[f];
  }
  return passes;
}

// The other way round: start from every body, drop every body not bound to the aggregate of
// those left, until none is dropped. A shattered body in the gravity regime has no large
// fragment to seed BA99's growth from, but its bulk is bound to itself: this finds it.
int shed(const std::vector<Body>& bodies, std::vector<bool>& in, double G) {
  int passes = 0;
  for (bool shrank = true; shrank;) {
    ++passes;
    shrank = false;
    const Aggregate a = aggregate_of(bodies, in);
    if (!(a.mass > 0.0)) break;
    std::vector<bool> leaving(bodies.size(), false);
    for (std::size_t f = 0; f < bodies.size(); ++f) {
      if (in[f] && !bound_to(bodies[f], a, G)) leaving[f] = shrank = true;
    }
    for (std::size_t f = 0; f < bodies.size(); ++f) in[f] = in[f] && !leaving[f];
  }
  return passes;
}

// Mass, centre, velocity, spin and members of the bodies in; the first `fragments` bodies are
// the catalogue's fragments (members), the rest dust points (counted).
BoundRemnant remnant_of(const std::vector<Body>& bodies, const std::vector<bool>& in,
                        std::size_t fragments, int passes) {
  BoundRemnant r;
  const Aggregate a = aggregate_of(bodies, in);
  r.mass = a.mass;
  r.centre = a.centre;
  r.velocity = a.velocity;
  r.iterations = passes;
  // Spin: L and I about the centre of mass (parallel-axis theorem for each body's own
  // inertia), omega = I^-1 L.
  Eigen::Matrix3d I = Eigen::Matrix3d::Zero();
  for (std::size_t f = 0; f < bodies.size(); ++f) {
    if (!in[f]) continue;
    const Body& F = bodies[f];
    if (f < fragments) {
      r.members.push_back(static_cast<std::int64_t>(f));
    } else {
      r.dust_mass += F.mass;
      ++r.dust_points;
    }
    const Eigen::Vector3d d = F.centre - r.centre;
    r.angular_momentum += F.angular_momentum + F.mass * d.cross(F.velocity - r.velocity);
    I += F.inertia + F.mass * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
  }
  const Eigen::FullPivLU<Eigen::Matrix3d> lu(I);
  if (lu.isInvertible()) r.omega = lu.solve(r.angular_momentum);
  return r;
}

}  // namespace

BoundRemnant bound_remnant(const FragmentCatalogue& cat, double G) {
  const std::vector<Body> bodies = fragment_bodies(cat);
  if (bodies.empty()) return {};
  std::vector<bool> in(bodies.size(), false);
  in[0] = true;  // the catalogue is sorted by mass: the seed is the largest fragment
  const int passes = grow(bodies, in, G);
  return remnant_of(bodies, in, bodies.size(), passes);
}

BoundRemnant bound_remnant_with_dust(const FragmentCatalogue& cat, const ParticleStore& store,
                                     double G) {
  std::vector<Body> bodies = fragment_bodies(cat);
  const std::size_t fragments = bodies.size();
  if (!store.has(IField::fragment)) {
    throw std::invalid_argument("bound remnant with dust: the store has no fragment labels");
  }
  // Dust points in id order (storage order otherwise), so the sums do not depend on storage.
  const auto label = store.col(IField::fragment);
  std::vector<std::size_t> dust;
  for (std::size_t p = 0; p < store.size(); ++p) {
    if (label[p] < 0) dust.push_back(p);
  }
  if (store.has(IField::id)) {
    const auto id = store.col(IField::id);
    std::sort(dust.begin(), dust.end(),
              [&](std::size_t i, std::size_t j) { return id[i] < id[j]; });
  }
  const auto col = [&](Field f, std::size_t p) { return store.col(f)[p]; };
  for (std::size_t p : dust) {
    Body b;
    b.mass = col(Field::mass, p);
    b.centre = {col(Field::x, p), col(Field::y, p), col(Field::z, p)};
    b.velocity = {col(Field::vx, p), col(Field::vy, p), col(Field::vz, p)};
    bodies.push_back(b);
  }
  if (bodies.empty()) return {};
  // BA99's growth from the largest fragment, and the bulk bound to itself (shed, then grown
  // again from what is left): the larger of the two bound aggregates is the remnant.
  std::vector<bool> from_fragment(bodies.size(), false), from_all(bodies.size(), true);
  int passes_fragment = 0;
  if (fragments > 0) {
    from_fragment[0] = true;
    passes_fragment = grow(bodies, from_fragment, G);
  }
  int passes_all = shed(bodies, from_all, G);
  if (std::find(from_all.begin(), from_all.end(), true) != from_all.end()) {
    passes_all += grow(bodies, from_all, G);
  }
  BoundRemnant a = remnant_of(bodies, from_fragment, fragments, passes_fragment);
  BoundRemnant b = remnant_of(bodies, from_all, fragments, passes_all);
  BoundRemnant& r = b.mass > a.mass ? b : a;
  r.with_dust = true;
  r.seed = &r == &b ? "self-bound bulk" : "largest fragment";
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
      "{{\n  \"criterion\": \"Benz & Asphaug 1999 iterative energy criterion, fragments {} as "
      "point masses{}\",\n  \"mass_kg\": {:.17g},\n  \"mass_fraction\": {:.17g},\n"
      "  \"dust_mass_kg\": {:.17g},\n  \"dust_points\": {},\n"
      "  \"centre_m\": {},\n  \"velocity_m_per_s\": {},\n  \"speed_m_per_s\": {:.17g},\n"
      "  \"angular_momentum_kg_m2_per_s\": {},\n  \"spin_rad_per_s\": {},\n"
      "  \"spin_rate_rad_per_s\": {:.17g},\n  \"fragments\": [{}],\n  \"passes\": {}\n}}\n",
      r.with_dust ? "and dust points" : "", r.with_dust ? ", seed: " + r.seed : ", dust excluded",
      r.mass, cat.total_mass > 0.0 ? r.mass / cat.total_mass : 0.0, r.dust_mass, r.dust_points,
      vec(r.centre), vec(r.velocity), r.speed(), vec(r.angular_momentum), vec(r.omega), r.spin(),
      ids, r.iterations);
  if (!out) throw std::runtime_error(fmt::format("error writing {}", file.string()));
}

}  // namespace shatter
