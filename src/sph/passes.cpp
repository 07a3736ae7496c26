// The particle passes of the SPH step (include/shatter/sph/solver.hpp): the kick (step 1), the
// rates gather pass (step 2, BA95 Eqs. 16 and 18), the material update (step 3), the drift
// (step 4) and the forces gather pass (step 6, BA95 Eq. 17 with Monaghan's viscosity).

#include <algorithm>
#include <cmath>
#include <cstring>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <tbb/parallel_for.h>

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

void SphSolver::Impl::rates(double dt, double dt_kick) {
  ParticleStore& P = s.particles_;
  midpoint_smoothing_lengths(dt);
  if (mirrors) {
    mirror_scalar(h_mid.data(), P.size());
    refresh_ghost_state();  // v^{n+1/2} of the images
  }
  ks::PairInputs in = inputs();
  in.h = h_mid.data();
  ks::RateOutputs out;
  for (int c = 0; c < 6; ++c) out.deps[c] = P.col(kDepsOrder[c]).data();
  for (int c = 0; c < 3; ++c) out.dspin[c] = P.col(kSpinOrder[c]).data();
  out.rho = P.col(Field::rho).data();
  if (s.sph_.continuity == Continuity::normalized) {
    // rho^n of the neighbours, read while the pass overwrites the column (the images' copy,
    // erho, is already separate).
    if (!mirrors) {
      const auto r = P.col(Field::rho);
      rho_n.resize(P.size());
      std::copy(r.begin(), r.end(), rho_n.begin());
    }
    out.rho_n = mirrors ? erho.data() : rho_n.data();
  }
  const ks::KickHeating kick{.pair_w = pair_w.data(),
                             .pair_mask = pair_mask.data(),
                             .ax = ax.data(),
                             .ay = ay.data(),
                             .az = az.data(),
                             .dt_kick = dt_kick,
                             .heat = heat.data()};
  const std::size_t n = P.size();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunk_w.size(), 1),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t c = r.begin(); c < r.end(); ++c) {
                        std::size_t w = chunk_w[c], g = chunk_mask[c];
                        const std::size_t end = std::min(n, (c + 1) * kPairGrain);
                        for (std::size_t i = c * kPairGrain; i < end; ++i) {
                          // The pairs within support at x^n and h^n, compacted by the forces
                          // pass of the last step (or of the constructor or restore()).
                          w += ks::rates_particle<simd::Batch>(
                              in, search.begin_of(i), active_count[i], i, dt, out, kick, w, g);
                          g += groups(active_count[i]);
                        }
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

namespace {

// Room for n entries in v, grown by an eighth when short (as the search's list buffers). Growing
// to the exact count re-allocated (and copied) at nearly every list build and every step of a
// compressing flow: in the laboratory impact that copy and its page faults were 15 % of the
// run (docs/performance.md, SPH round 5). The content is not kept across the growth (it is
// rewritten before it is read), so the old array is dropped before the new one is made.
template <class V>
void make_room(V& v, std::size_t n) {
  if (v.capacity() < n) {
    const std::size_t cap = std::max(n, v.capacity() + v.capacity() / 8);
    V().swap(v);
    v.reserve(cap);
  }
  v.resize(n);
}

}  // namespace

// Each list re-arranged so that its pairs within support come first, in ascending index order
// (a Verlet list's skin entries after them), which the forces pass and the next step's rates
// pass use: it runs at these same positions and h. The viscous weights' masks are kept for those
// pairs only (chunk_mask: where each chunk's start), 53 instead of 75 per particle in the
// benchmark's cube.
void SphSolver::Impl::compact_lists(const ks::PairInputs& in) {
  const std::size_t n = s.particles_.size();
  const std::size_t chunks = (n + kPairGrain - 1) / kPairGrain;
  active_count.resize(n);
  chunk_mask.resize(chunks + 1);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks, 1),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      std::vector<std::uint32_t>& scratch = rest.local();
                      for (std::size_t c = r.begin(); c < r.end(); ++c) {
                        std::size_t masks = 0;
                        const std::size_t end = std::min(n, (c + 1) * kPairGrain);
                        for (std::size_t i = c * kPairGrain; i < end; ++i) {
                          const std::size_t count = search.count(i);
                          if (scratch.size() < count + 8) scratch.resize(count + 8);
                          const std::size_t sorted = lists_sorted ? count : active_count[i];
                          active_count[i] = static_cast<std::uint32_t>(ks::partition_within_support(
                              in, search.rearrange(i), count, sorted, i, scratch.data()));
                          masks += groups(active_count[i]);
                        }
                        chunk_mask[c + 1] = masks;
                      }
                    });
  lists_sorted = false;
  chunk_mask[0] = 0;
  for (std::size_t c = 0; c < chunks; ++c) chunk_mask[c + 1] += chunk_mask[c];
  make_room(pair_mask, chunk_mask[chunks]);
}

// A new layout of pair_w after a forces pass in which chunks found no room: each chunk's weights
// (from its room, or from `spill` where it had none) at the start of a new room of an eighth
// more than it needs (and 64), in chunk order. pair_w does not shrink (the search borrows it).
// In place, so that no second array is live: pair_w grows (realloc, its content kept), then the
// chunks that kept their weights in their rooms move, those moving down in chunk order and those
// moving up in reverse order (old rooms and new rooms are each disjoint and in chunk order, so no
// move overwrites weights not yet moved), and the spilt chunks' weights are copied in last.
void SphSolver::Impl::place_weights() {
  const std::size_t chunks = chunk_w.size();
  std::vector<std::size_t> at(chunks);
  std::size_t total = 0;
  for (std::size_t c = 0; c < chunks; ++c) {
    at[c] = total;
    total += chunk_w_count[c] + chunk_w_count[c] / 8 + 64;
  }
  pair_w.grow(total);
  double* w = pair_w.data();
  const auto move = [&](std::size_t c) {
    if (spill[c].empty() && chunk_w_count[c] > 0) {
      std::memmove(w + at[c], w + chunk_w[c], chunk_w_count[c] * sizeof(double));
    }
  };
  for (std::size_t c = 0; c < chunks; ++c) {
    if (at[c] <= chunk_w[c]) move(c);
  }
  for (std::size_t c = chunks; c-- > 0;) {
    if (at[c] > chunk_w[c]) move(c);
  }
  for (std::size_t c = 0; c < chunks; ++c) {
    if (!spill[c].empty()) std::copy_n(spill[c].data(), chunk_w_count[c], w + at[c]);
    std::vector<double>().swap(spill[c]);
    chunk_w[c] = at[c];
    chunk_room[c] = chunk_w_count[c] + chunk_w_count[c] / 8 + 64;
  }
#if defined(__GLIBC__)
  // The spilt weights just freed (up to all of them, at the first pass) leave free pages inside
  // the heap that stay resident, and on 2 threads in a second malloc arena that the main
  // thread's allocations do not reuse: hand them back (laboratory impact to 2 us on 2 threads:
  // peak RSS 77.3 -> 75.3 MB; docs/performance.md, session 23: SPH, "Memory"). A re-layout
  // comes every ~10 steps (23 in the 221 steps to 5 us); the trim's cost was not measurable.
  malloc_trim(0);
#endif
}

// The forces pass over chunk c's particles, their weights written straight into the chunk's room
// in pair_w; a particle that might not fit (it writes at most its pair count) moves them to the
// thread's buffer, and they end in spill[c]. Returns whether they did.
bool SphSolver::Impl::forces_chunk(std::size_t c, const ks::PairInputs& in,
                                   const ks::ForceInputs& f) {
  const std::size_t begin = c * kPairGrain;
  const std::size_t end = std::min(s.particles_.size(), begin + kPairGrain);
  ks::ForceOutputs out{ax.data(),       ay.data(),    az.data(),
                       heat.data(),     h_mid.data(), pair_w.data() + chunk_w[c],
                       pair_mask.data()};
  std::size_t w = 0, g = chunk_mask[c];
  bool spilt = false;
  for (std::size_t i = begin; i < end; ++i) {
    if (!spilt && w + active_count[i] > chunk_room[c]) {
      std::vector<double>& packed = packing.local();
      std::size_t pairs = w;
      for (std::size_t k = i; k < end; ++k) pairs += active_count[k];
      if (packed.size() < pairs) packed.resize(pairs);
      std::copy(out.pair_w, out.pair_w + w, packed.data());
      out.pair_w = packed.data();
      spilt = true;
    }
    w += ks::forces_particle<simd::Batch>(in, f, search.begin_of(i), active_count[i], i, out, w, g);
    g += groups(active_count[i]);
  }
  chunk_w_count[c] = w;
  if (spilt) {
    // One past the weights, so that a spilt chunk is never empty (place_weights).
    spill[c].reserve(w + 1);
    spill[c].assign(out.pair_w, out.pair_w + w);
    spill[c].push_back(0.0);
  }
  return spilt;
}

void SphSolver::Impl::forces() {
  ParticleStore& P = s.particles_;
  const std::size_t n = P.size();
  const double* rho = P.col(Field::rho).data();
  const double* sig[6];
  for (int c = 0; c < 6; ++c) sig[c] = P.col(kStressOrder[c]).data();
  const bool normalized = s.sph_.continuity == Continuity::normalized;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (int c = 0; c < 6; ++c) {
                        for (std::size_t p = r.begin(); p < r.end(); ++p) {
                          a_stress[c][p] = normalized ? sig[c][p] : sig[c][p] / (rho[p] * rho[p]);
                        }
                      }
                    });
  if (mirrors) {
    mirror_stress(n);
    refresh_ghost_state();
  }
  const ks::PairInputs in = inputs();
  ks::ForceInputs f;
  for (int c = 0; c < 6; ++c) f.a_stress[c] = a_stress[c].data();
  f.soundspeed = mirrors ? ec.data() : P.col(Field::soundspeed).data();
  f.normalized = normalized;
  f.viscosity.alpha = s.sph_.alpha;
  f.viscosity.beta = s.sph_.beta;
  if (switch_on) {
    if (mirrors) mirror_scalar(alpha.data(), n);
    f.alpha = alpha.data();
  }
  for (int d = 0; d < 3; ++d) f.gravity[d] = s.config_.gravity[d];
  compact_lists(in);
  const std::size_t chunks = chunk_mask.size() - 1;
  // Chunks new since the last layout have no room: they spill, and the pass lays pair_w out anew.
  chunk_w.resize(chunks, 0);
  chunk_room.resize(chunks, 0);
  chunk_w_count.resize(chunks);
  spill.resize(chunks);
  pair_w.grow(1);  // a valid pointer for the rates pass
  std::atomic<bool> spilled{false};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks, 1),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t c = r.begin(); c < r.end(); ++c) {
                        if (forces_chunk(c, in, f)) spilled.store(true, std::memory_order_relaxed);
                      }
                    });
  if (spilled.load()) place_weights();
  if (s.config_.self_gravity.self) add_self_gravity();
  // The images' a^n, for the next kick's viscous heat (rates pass).
  if (mirrors) mirror_vector(ax.data(), ay.data(), az.data(), n);
}

}  // namespace shatter::sph
