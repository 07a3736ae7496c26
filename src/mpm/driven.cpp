#include "mpm/driven.hpp"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <stdexcept>

#include <fmt/format.h>

namespace shatter::mpm {

DrivenBodies::DrivenBodies(const ParticleStore& P, std::span<const std::int32_t> bodies)
    : bodies_(bodies.begin(), bodies.end()) {
  std::sort(bodies_.begin(), bodies_.end());
  bodies_.erase(std::unique(bodies_.begin(), bodies_.end()), bodies_.end());
  if (bodies_.empty()) return;
  if (!P.has(IField::body) || !P.has(IField::id)) {
    throw std::invalid_argument("driven bodies: the particle store has no body or id column");
  }
  const auto body = P.col(IField::body);
  const auto id = P.col(IField::id);
  std::vector<std::size_t> members;
  std::vector<std::size_t> count(bodies_.size(), 0);
  for (std::size_t p = 0; p < P.size(); ++p) {
    const auto it = std::lower_bound(bodies_.begin(), bodies_.end(), body[p]);
    if (it == bodies_.end() || *it != body[p]) continue;
    members.push_back(p);
    ++count[static_cast<std::size_t>(it - bodies_.begin())];
  }
  for (std::size_t k = 0; k < bodies_.size(); ++k) {
    if (count[k] == 0) {
      throw std::invalid_argument(
          fmt::format("driven body {}: no particle of this body in the store", bodies_[k]));
    }
  }
  std::sort(members.begin(), members.end(),
            [&](std::size_t a, std::size_t b) { return id[a] < id[b]; });
  const double* V[3] = {P.col(Field::vx).data(), P.col(Field::vy).data(), P.col(Field::vz).data()};
  for (const std::size_t p : members) {
    if (!ids_.empty() && ids_.back() == id[p]) {
      throw std::invalid_argument(fmt::format("driven bodies: particle id {} twice", id[p]));
    }
    ids_.push_back(id[p]);
    for (int d = 0; d < 3; ++d) v_.push_back(V[d][p]);
  }
}

bool DrivenBodies::driven(std::int64_t body) const {
  return std::binary_search(bodies_.begin(), bodies_.end(), body);
}

const double* DrivenBodies::velocity(std::int64_t id) const {
  const auto it = std::lower_bound(ids_.begin(), ids_.end(), id);
  if (it == ids_.end() || *it != id) return nullptr;  // a point made after the drive was set
  return v_.data() + 3 * static_cast<std::size_t>(it - ids_.begin());
}

double DrivenBodies::constrain(SparseGrid& grid, double dt) const {
  auto& N = grid.nodes();
  double* vel[3] = {N.px.data(), N.py.data(), N.pz.data()};
  double* acc[3] = {N.fx.data(), N.fy.data(), N.fz.data()};
  double work = 0.0;
  // Serial over the nodes in first-touch order (particle order): the work sum is the same for
  // any thread count.
  for (const std::uint32_t i : nodes_) {
    const double M = N.mass[i];
    if (!(M > 0.0)) continue;
    for (int d = 0; d < 3; ++d) {
      const double target = node_p_[3 * i + static_cast<std::size_t>(d)] / node_m_[i];
      const double dv = target - vel[d][i];
      // v^{n+1/2} = v^{n-1/2} + a dt (Eq. 27): the acceleration carries the same change, so that
      // FLIP particles (v_p += a dt) feel the drive, not only PIC/APIC ones.
      if (dt > 0.0) acc[d][i] += dv / dt;
      vel[d][i] = target;
      work += M * dv * target;  // impulse J_I times the driver's velocity (see driven.hpp)
    }
  }
  return work;
}

void DrivenBodies::hold(ParticleStore& P) const {
  const auto body = P.col(IField::body);
  const auto id = P.col(IField::id);
  double* V[3] = {P.col(Field::vx).data(), P.col(Field::vy).data(), P.col(Field::vz).data()};
  for (std::size_t p = 0; p < P.size(); ++p) {
    if (!driven(body[p])) continue;
    const double* v = velocity(id[p]);
    if (v == nullptr) continue;
    for (int d = 0; d < 3; ++d) V[d][p] = v[d];
  }
}

parallel::ExactSum DrivenBodies::set_particles(ParticleStore& P, double* dx, double* dy, double* dz,
                                               double dt, const Boundaries* outflow) const {
  const auto body = P.col(IField::body);
  const auto id = P.col(IField::id);
  const auto mass = P.col(Field::mass);
  double* V[3] = {P.col(Field::vx).data(), P.col(Field::vy).data(), P.col(Field::vz).data()};
  double* D[3] = {dx, dy, dz};
  const double* X[3] = {P.col(Field::x).data(), P.col(Field::y).data(), P.col(Field::z).data()};
  parallel::ExactSum kinetic;
  for (std::size_t p = 0; p < P.size(); ++p) {
    if (!driven(body[p])) continue;
    const double* v = velocity(id[p]);
    if (v == nullptr) continue;
    for (int d = 0; d < 3; ++d) {
      V[d][p] = v[d];
      D[d][p] = v[d] * dt;
    }
    // Out of the sum where the point leaves (the outflow stage's test: dx + x past a face).
    if (outflow != nullptr &&
        outflow->outside_outflow(D[0][p] + X[0][p], D[1][p] + X[1][p], D[2][p] + X[2][p])) {
      continue;
    }
    kinetic.add(0.5 * mass[p] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
  }
  return kinetic;
}

}  // namespace shatter::mpm
