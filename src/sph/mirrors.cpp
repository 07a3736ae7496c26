// The boundaries of the SPH step (DESIGN.md "The SPH step", boundaries): mirror particles across
// the symmetry and slip faces, and the faces' effect on the drift (reflection back, outflow).

#include <algorithm>

#include "sph/solver_impl.hpp"

namespace shatter::sph {

double SphSolver::Impl::plane(std::size_t face) const {
  return face % 2 == 0 ? s.config_.domain.lo[static_cast<int>(face / 2)]
                       : s.config_.domain.hi[static_cast<int>(face / 2)];
}

// The mirror particles for the current positions and h: every image of a real particle that
// lies within 2 max h of a reflecting face (the largest support h_i + h_j, so every image that
// can be a neighbour), including the edge and corner images across two or three faces. Serial
// and in index order, so the images and their numbering are the same on any thread count.
// With a skin the images within 2 max h + skin are made, and kept (their positions and h
// follow their sources, place_ghosts()) while the lists are reused.
void SphSolver::Impl::make_ghosts(double hmax) {
  if (!mirrors) return;
  const ParticleStore& P = s.particles_;
  const std::size_t n = P.size();
  const double* X[3] = {P.col(Field::x).data(), P.col(Field::y).data(), P.col(Field::z).data()};
  const double reach = 2.0 * hmax + skin_abs;
  ghosts.clear();
  for (std::size_t p = 0; p < n; ++p) {
    std::int8_t opt[3][3];
    int count[3];
    for (int a = 0; a < 3; ++a) {
      count[a] = 0;
      opt[a][count[a]++] = 0;
      const auto lo = static_cast<std::size_t>(2 * a), hi = lo + 1;
      if (mirror_face[lo] && X[a][p] - plane(lo) < reach) opt[a][count[a]++] = -1;
      if (mirror_face[hi] && plane(hi) - X[a][p] < reach) opt[a][count[a]++] = 1;
    }
    if (count[0] + count[1] + count[2] == 3) continue;
    for (int i = 0; i < count[0]; ++i) {
      for (int j = 0; j < count[1]; ++j) {
        for (int k = 0; k < count[2]; ++k) {
          if (i == 0 && j == 0 && k == 0) continue;
          ghosts.push_back({static_cast<std::uint32_t>(p), {opt[0][i], opt[1][j], opt[2][k]}});
        }
      }
    }
  }
  size_ghost_columns(n + ghosts.size());
  place_ghosts();
}

// The per-point arrays for n real particles and their images (m points in all). A column that
// must grow takes m and a 32nd more: std::vector's resize would double it (the real particles'
// columns, sized n, would take 2n for a few thousand images: ~5 MB of the laboratory impact's
// heap peak), and the slack absorbs the image count's growth from build to build.
void SphSolver::Impl::size_ghost_columns(std::size_t m) {
  const auto grow = [m](AlignedVector<double>& v) {
    if (v.capacity() < m) v.reserve(m + m / 32);
    v.resize(m);
  };
  for (auto* v : {&h, &h_mid, &ax, &ay, &az, &ex, &ey, &ez, &evx, &evy, &evz, &em, &erho, &ec}) {
    grow(*v);
  }
  if (switch_on) grow(alpha);
  for (auto& v : a_stress) grow(v);
}

// Positions (the reflections of their sources' current positions) and h of the images.
void SphSolver::Impl::place_ghosts() {
  const ParticleStore& P = s.particles_;
  const std::size_t n = P.size();
  const double* X[3] = {P.col(Field::x).data(), P.col(Field::y).data(), P.col(Field::z).data()};
  double* E[3] = {ex.data(), ey.data(), ez.data()};
  for (int a = 0; a < 3; ++a) std::copy(X[a], X[a] + n, E[a]);
  for (std::size_t k = 0; k < ghosts.size(); ++k) {
    const Mirror& g = ghosts[k];
    for (int a = 0; a < 3; ++a) {
      const double x = X[a][g.src];
      const auto face = static_cast<std::size_t>(2 * a + (g.side[a] > 0 ? 1 : 0));
      E[a][n + k] = g.side[a] == 0 ? x : 2.0 * plane(face) - x;
    }
    h[n + k] = h[g.src];
  }
}

// Reflected copies of a per-particle vector (sign -1 on reflected axes) or scalar.
void SphSolver::Impl::mirror_vector(double* vx, double* vy, double* vz, std::size_t n) const {
  for (std::size_t k = 0; k < ghosts.size(); ++k) {
    const Mirror& g = ghosts[k];
    vx[n + k] = g.side[0] != 0 ? -vx[g.src] : vx[g.src];
    vy[n + k] = g.side[1] != 0 ? -vy[g.src] : vy[g.src];
    vz[n + k] = g.side[2] != 0 ? -vz[g.src] : vz[g.src];
  }
}
void SphSolver::Impl::mirror_scalar(double* v, std::size_t n) const {
  for (std::size_t k = 0; k < ghosts.size(); ++k) v[n + k] = v[ghosts[k].src];
}

// The state the gather passes read, real then mirrored (velocity, mass, density, sound speed).
void SphSolver::Impl::refresh_ghost_state() {
  if (!mirrors) return;
  const ParticleStore& P = s.particles_;
  const std::size_t n = P.size();
  const std::pair<Field, double*> copies[] = {
      {Field::vx, evx.data()},  {Field::vy, evy.data()},   {Field::vz, evz.data()},
      {Field::mass, em.data()}, {Field::rho, erho.data()}, {Field::soundspeed, ec.data()}};
  for (const auto& [f, to] : copies) {
    const double* from = P.col(f).data();
    std::copy(from, from + n, to);
  }
  mirror_vector(evx.data(), evy.data(), evz.data(), n);
  mirror_scalar(em.data(), n);
  mirror_scalar(erho.data(), n);
  mirror_scalar(ec.data(), n);
}

// sigma^{ab} / rho^2 of the images: negated when exactly one of a, b is a reflected axis.
void SphSolver::Impl::mirror_stress(std::size_t n) {
  static constexpr int kAxes[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {1, 2}, {0, 2}};
  for (std::size_t k = 0; k < ghosts.size(); ++k) {
    const Mirror& g = ghosts[k];
    for (int c = 0; c < 6; ++c) {
      const bool flip = (g.side[kAxes[c][0]] != 0) != (g.side[kAxes[c][1]] != 0);
      const double v = a_stress[c][g.src];
      a_stress[c][n + k] = flip ? -v : v;
    }
  }
}

// A real particle that crossed a reflecting face during the drift is reflected back (position
// and normal velocity, which keeps its kinetic energy): it met its own image.
void SphSolver::Impl::reflect_after_drift() {
  if (!mirrors) return;
  ParticleStore& P = s.particles_;
  const std::size_t n = P.size();
  double* X[3] = {P.col(Field::x).data(), P.col(Field::y).data(), P.col(Field::z).data()};
  double* V[3] = {P.col(Field::vx).data(), P.col(Field::vy).data(), P.col(Field::vz).data()};
  for (std::size_t face = 0; face < 6; ++face) {
    if (!mirror_face[face]) continue;
    const int a = static_cast<int>(face / 2);
    const double p0 = plane(face), sign = face % 2 == 0 ? 1.0 : -1.0;
    for (std::size_t p = 0; p < n; ++p) {
      if (sign * (X[a][p] - p0) < 0.0) {
        X[a][p] = 2.0 * p0 - X[a][p];
        V[a][p] = -V[a][p];
      }
    }
  }
}

// Particles beyond an outflow face leave, their energy booked as outflow (as MPM's outflow),
// with the velocity and internal energy at t^n+1/2 (a^{n+1} is not made for them).
void SphSolver::Impl::outflow_after_drift() {
  if (!outflows) return;
  ParticleStore& P = s.particles_;
  const std::size_t n = P.size();
  const double* X[3] = {P.col(Field::x).data(), P.col(Field::y).data(), P.col(Field::z).data()};
  const double* V[3] = {P.col(Field::vx).data(), P.col(Field::vy).data(), P.col(Field::vz).data()};
  leaving.assign(n, 0);
  const double* m = P.col(Field::mass).data();
  const double* e = P.col(Field::energy).data();
  const Vec3 g = s.config_.gravity;
  double carried = 0.0;
  for (std::size_t p = 0; p < n; ++p) {
    bool out = false;
    for (std::size_t face = 0; face < 6; ++face) {
      if (!outflow_face[face]) continue;
      const double d = X[face / 2][p] - plane(face);
      out = out || (face % 2 == 0 ? d < 0.0 : d > 0.0);
    }
    if (!out) continue;
    leaving[p] = 1;
    carried += 0.5 * m[p] * (V[0][p] * V[0][p] + V[1][p] * V[1][p] + V[2][p] * V[2][p]) +
               m[p] * e[p] - m[p] * (g.x() * X[0][p] + g.y() * X[1][p] + g.z() * X[2][p]);
  }
  if (P.remove_if(leaving) == 0) return;
  drop_leaving_switch(n);
  lists_valid = false;
  if (P.size() == 0) {
    throw NumericalError("every particle has left through the outflow boundaries", 0,
                         s.clock_.step);
  }
  s.energy_.outflow += carried;
}

// The columns the gather passes read: with mirror particles the copies (real, then images),
// without them the store's columns.
ks::PairInputs SphSolver::Impl::inputs() {
  ParticleStore& P = s.particles_;
  const auto read = [&](Field f, AlignedVector<double>& copy) {
    return mirrors ? copy.data() : P.col(f).data();
  };
  ks::PairInputs in;
  in.x = read(Field::x, ex);
  in.y = read(Field::y, ey);
  in.z = read(Field::z, ez);
  in.vx = read(Field::vx, evx);
  in.vy = read(Field::vy, evy);
  in.vz = read(Field::vz, evz);
  in.mass = read(Field::mass, em);
  in.rho = read(Field::rho, erho);
  in.h = h.data();
  return in;
}

}  // namespace shatter::sph
