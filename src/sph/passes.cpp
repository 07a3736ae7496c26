// The particle passes of the SPH step (include/shatter/sph/solver.hpp): the kick (step 1), the
// rates pass (step 2, BA95 Eqs. 16 and 18), the material update (step 3) and the drift (step 4).
// The forces pass (step 6) and the pair passes' tiles are in tiles.cpp.

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "sph/pairs.hpp"
#include "sph/solver_impl.hpp"

namespace shatter::sph {

double kinetic_energy(const ParticleStore& P) {
  const auto m = P.col(Field::mass);
  const auto vx = P.col(Field::vx), vy = P.col(Field::vy), vz = P.col(Field::vz);
  return deterministic_sum(P.size(), [&](std::size_t p) {
    return 0.5 * m[p] * (vx[p] * vx[p] + vy[p] * vy[p] + vz[p] * vz[p]);
  });
}

void SphSolver::Impl::kick(double dt_kick) {
  ParticleStore& P = s.particles_;
  double* v[3] = {P.col(Field::vx).data(), P.col(Field::vy).data(), P.col(Field::vz).data()};
  const double* a[3] = {ax.data(), ay.data(), az.data()};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, P.size(), kGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (int d = 0; d < 3; ++d) {
                        for (std::size_t p = r.begin(); p < r.end(); ++p) {
                          v[d][p] += a[d][p] * dt_kick;
                        }
                      }
                    });
}

// The prescribed velocities at t^{n+1/2} (set_velocity_constraint), the kinetic energy they
// add or remove booked as boundary work.
void SphSolver::Impl::constrain_velocities(double t_half) {
  if (!s.constraint_) return;
  const double before = kinetic_energy(s.particles_);
  s.constraint_(t_half, s.particles_);
  s.energy_.boundary_work += before - kinetic_energy(s.particles_);
}

// The kick's viscous heat (made in the rates pass, in `heat`) into the energy at t^n, before the
// material update reads it.
void SphSolver::Impl::heat_from_kick() {
  ParticleStore& P = s.particles_;
  double* e = P.col(Field::energy).data();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, P.size(), kGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t p = r.begin(); p < r.end(); ++p) e[p] += heat[p];
                    });
}

// h^{n+1/2} for the rates pass. The forces at t^n and t^{n+1} use h(rho^n) and h(rho^{n+1});
// the stress work matches their mean to second order only if the strain rate between them uses
// the mean smoothing length too (with h^n the total energy error was first order in dt: 9e-4
// and 4.6e-4 at CFL 0.3 and 0.15 for the colliding spheres without viscosity; with fixed h,
// 8.9e-5 and 2.5e-5). rho^{n+1} is not known before the pass, so it is predicted from the
// last step's volume change (the deps columns, which a checkpoint holds):
// rho^{n+1} ~ rho^n / (1 + tr deps^{n-1/2} dt / dt_prev), an O(dt^2) error in h^{n+1/2}.
void SphSolver::Impl::midpoint_smoothing_lengths(double dt) {
  ParticleStore& P = s.particles_;
  const double ratio = s.clock_.dt_prev > 0.0 ? dt / s.clock_.dt_prev : 0.0;
  const double* d[3] = {P.col(Field::deps_xx).data(), P.col(Field::deps_yy).data(),
                        P.col(Field::deps_zz).data()};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, P.size(), kGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t p = r.begin(); p < r.end(); ++p) {
                        const double grow = 1.0 + (d[0][p] + d[1][p] + d[2][p]) * ratio;
                        // h ~ rho^{-1/3}; a predicted collapse (grow <= 0) keeps h^n.
                        h_mid[p] = grow > 0.0 ? 0.5 * h[p] * (1.0 + std::cbrt(grow)) : h[p];
                      }
                    });
}

// The rates pass in the symmetric form (kernels/sph/pairs.hpp, rates_upper) over the tiles of
// the last forces pass (tiles.cpp: the same compacted lists), the velocity gradient's sums and
// the kick's heat in rows8 and rows2, then turned into the increments and rho^{n+1} per particle
// (write_rates) and `heat`.
void SphSolver::Impl::rates(double dt, double dt_kick) {
  ParticleStore& P = s.particles_;
  const std::size_t n = P.size();
  midpoint_smoothing_lengths(dt);
  if (mirrors) {
    mirror_scalar(h_mid.data(), n);
    refresh_ghost_state();  // v^{n+1/2} of the images
  }
  ks::PairInputs in = inputs();
  in.h = h_mid.data();
  ks::RateOutputs out;
  for (int c = 0; c < 6; ++c) out.deps[c] = P.col(kDepsOrder[c]).data();
  for (int c = 0; c < 3; ++c) out.dspin[c] = P.col(kSpinOrder[c]).data();
  out.rho = P.col(Field::rho).data();
  rows8.resize(8 * n);
  rows2.resize(2 * n);
  const ks::RateSums sums{rows8.data(), rows2.data()};
  // rho^n of every particle for the normalized continuity: the column itself (the pair pass
  // does not write it), or the images' copy.
  const double* rho_n =
      s.sph_.continuity == Continuity::normalized ? (mirrors ? erho.data() : out.rho) : nullptr;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      std::fill(rows8.data() + 8 * r.begin(), rows8.data() + 8 * r.end(), 0.0);
                      std::fill(rows2.data() + 2 * r.begin(), rows2.data() + 2 * r.end(), 0.0);
                    });
  const ks::KickHeating kick{.pair_w = pair_w.data(),
                             .pair_mask = pair_mask.data(),
                             .ax = ax.data(),
                             .ay = ay.data(),
                             .az = az.data(),
                             .dt_kick = dt_kick,
                             .heat = heat.data()};
  over_tiles([&](std::size_t c) {
    std::size_t w = chunk_w[c], g = chunk_mask[c];
    const std::size_t end = std::min(n, (c + 1) * kPairGrain);
    for (std::size_t i = c * kPairGrain; i < end; ++i) {
      // The pairs within support at x^n and h^n, compacted by the forces pass of the last step
      // (or of the constructor or restore()): their upper half.
      const std::size_t half = active_count[i] - upper_at[i];
      w += ks::rates_upper<simd::Batch>(in, search.begin_of(i) + upper_at[i], half, i, n, dt, rho_n,
                                        sums, kick, w, g);
      g += groups(half);
    }
  });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i < r.end(); ++i) {
                        double Lsum[3][3];
                        for (int c = 0; c < 8; ++c) Lsum[c / 3][c % 3] = rows8[8 * i + c];
                        Lsum[2][2] = rows2[2 * i];
                        ks::write_rates(Lsum, out.rho[i], dt, out, i);
                        heat[i] = rows2[2 * i + 1] * dt_kick;
                      }
                    });
}

void SphSolver::Impl::material(double dt) {
  // SPH has its own pairwise viscosity (and heating): the constitutive kernel's bulk viscosity
  // is switched off so that shocks are not damped (and heated) twice.
  const ConstitutiveContext ctx{dt, 0.0, ArtificialViscosity{0.0, 0.0}};
  for (const Group& g : s.particles_.groups()) {
    if (g.range.empty()) continue;
    s.materials_[static_cast<std::size_t>(g.material)]->update(s.particles_, g.range, ctx);
  }
}

void SphSolver::Impl::drift(double dt) {
  ParticleStore& P = s.particles_;
  double* X[3] = {P.col(Field::x).data(), P.col(Field::y).data(), P.col(Field::z).data()};
  const double* V[3] = {P.col(Field::vx).data(), P.col(Field::vy).data(), P.col(Field::vz).data()};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, P.size(), kGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (int d = 0; d < 3; ++d) {
                        for (std::size_t p = r.begin(); p < r.end(); ++p) X[d][p] += V[d][p] * dt;
                      }
                    });
}

}  // namespace shatter::sph
