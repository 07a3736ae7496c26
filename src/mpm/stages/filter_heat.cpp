// App. A.2 step 5b (SolverConfig::filter_heat): the kinetic energy a filtering transfer (XPIC,
// FMPM, the FLIP/PIC blend) removes in a step, booked as internal energy of the points that
// carried it. This is the kinetic-energy fix of DeBar (1974) for the momentum remap of
// staggered-grid ALE codes (Benson 1992, CMAME 99, "Computational methods in Lagrangian and
// Eulerian hydrocodes", remap section): the remap conserves momentum but not kinetic energy, and
// the difference is put into internal energy so that total energy is conserved. Here the
// "remap" is the filtered particle update and the reference is the plain FLIP update of the
// same step (G2P writes both):
//   K_removed = sum_p m_p |v_p^FLIP|^2 / 2 - sum_p m_p |v_p^filtered|^2 / 2,
//   e_p += K_removed w_p / (m_p sum_q w_q),   w_p = m_p |v_p^FLIP - v_p^filtered|^2 / 2.
// The weights are non-negative, so no point is cooled, and a point the filter left alone gets
// nothing. With a projection-like filter the cross term sum_p m_p (v^FLIP - v^f).v^f is small
// and K_removed ~ sum_p w_p; where the step's filter adds kinetic energy (K_removed <= 0) nothing
// is booked, and the total-energy error shows it. Both sums are exact, so the deposit is the
// same bits on any thread or rank count. Velocities only are read: momentum is untouched.

#include <array>

#include "mpm/loops.hpp"
#include "mpm/stages/stages.hpp"
#include "mpm/state.hpp"
#include "parallel/exact_reduce.hpp"

namespace shatter::mpm {
namespace {

void filter_heat(State& s) {
  if (s.transfer.filtered_share(s.filtering) == 0.0) return;  // a FLIP step: nothing removed
  ParticleStore& P = s.particles;
  const Scratch& sc = s.scratch;
  const auto m = P.col(Field::mass), vx = P.col(Field::vx), vy = P.col(Field::vy),
             vz = P.col(Field::vz);
  auto e = P.col(Field::energy);
  const double *fx = sc.flip_vx.data(), *fy = sc.flip_vy.data(), *fz = sc.flip_vz.data();
  // |v^FLIP - v^filtered|^2 / 2 of point p: its weight per unit mass.
  const auto spread = [&](std::size_t p) {
    const double d[3] = {fx[p] - vx[p], fy[p] - vy[p], fz[p] - vz[p]};
    return 0.5 * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  };
  parallel::ExactSum removed = exact_sum(P.size(), [&](std::size_t p) {
    const double flip = fx[p] * fx[p] + fy[p] * fy[p] + fz[p] * fz[p];
    const double kept = vx[p] * vx[p] + vy[p] * vy[p] + vz[p] * vz[p];
    return 0.5 * m[p] * flip - 0.5 * m[p] * kept;
  });
  parallel::ExactSum weights = exact_sum(P.size(), [&](std::size_t p) { return m[p] * spread(p); });
  if (s.dist()) {
    const std::array<parallel::ExactSum*, 2> both = {&removed, &weights};
    parallel::sum_over_ranks(s.ranks.comm, both);
  }
  const double K = removed.value(), W = weights.value();
  if (!(K > 0.0 && W > 0.0)) return;
  // e_p += K w_p / (m_p W) = (K / W) |v^FLIP - v^filtered|^2 / 2.
  const double per_weight = K / W;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, P.size(), kParticleGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t p = r.begin(); p < r.end(); ++p) {
                        e[p] += per_weight * spread(p);
                      }
                    });
}

}  // namespace

// kGrid is not read: declared so that the stage runs before the remap, not beside it, and its
// sum over the ranks never interleaves with the remap's halo exchange.
Stage filter_heat_stage(State& s) {
  return {"filter_heat",
          {kVelocity | FieldSet{Field::mass}, kMechanical | kClock | kGrid},
          {FieldSet{Field::energy}, 0},
          [&s] { filter_heat(s); }};
}

}  // namespace shatter::mpm
