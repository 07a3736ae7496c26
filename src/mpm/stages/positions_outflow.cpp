// The position update x^{n+1} = x^n + dx (after steps 6-7, which need the shape functions at
// x^n), and the outflow faces: particles past one leave the store with their energy booked.

#include <algorithm>

#include "mpm/loops.hpp"
#include "mpm/stages/stages.hpp"
#include "mpm/state.hpp"

namespace shatter::mpm {
namespace {

// x^n + dx is written over the displacement, whose buffer then becomes the position column, and
// the position column's buffer the displacement scratch: it holds x^n until the next step's G2P
// writes it, and the step retake takes the positions at t^n back from there (retake.hpp) instead
// of from a copy made before each step (24 B per particle). The same sum, so the same bits.
void advance_positions(State& s) {
  ParticleStore& P = s.particles;
  Scratch& sc = s.scratch;
  const double* X[3] = {P.col(Field::x).data(), P.col(Field::y).data(), P.col(Field::z).data()};
  double* D[3] = {sc.dx.data(), sc.dy.data(), sc.dz.data()};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, P.size(), kParticleGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (int d = 0; d < 3; ++d) {
                        for (std::size_t p = r.begin(); p < r.end(); ++p) D[d][p] += X[d][p];
                      }
                    });
  P.swap_column(Field::x, sc.dx);
  P.swap_column(Field::y, sc.dy);
  P.swap_column(Field::z, sc.dz);
}

// The departed particles' rows of the potential energy column (where it is stored: Scratch)
// are dropped so that its sum matches the remaining particles; G2P left them out of the
// kinetic energy's sum already.
void drop_departed(Scratch& sc, const std::vector<std::uint8_t>& leaving) {
  if (sc.potential.empty()) return;
  std::size_t k = 0;
  for (std::size_t p = 0; p < leaving.size(); ++p) {
    if (!leaving[p]) sc.potential[k++] = sc.potential[p];
  }
  sc.potential.resize(k);
}

void outflow(State& s) {
  if (!s.outflow_due) return;  // G2P's test found no point past a face (State::outflow_due)
  ParticleStore& P = s.particles;
  std::vector<std::uint8_t> leaving(P.size(), 0);
  const auto x = P.col(Field::x), y = P.col(Field::y), z = P.col(Field::z);
  const auto m = P.col(Field::mass), e = P.col(Field::energy);
  const auto vx = P.col(Field::vx), vy = P.col(Field::vy), vz = P.col(Field::vz);
  const Vec3 g = s.config.gravity;
  parallel::ExactSum carried, carried_internal;
  for (std::size_t p = 0; p < P.size(); ++p) {
    if (!s.boundaries.outside_outflow(x[p], y[p], z[p])) continue;
    leaving[p] = 1;
    carried_internal.add(m[p] * e[p]);
    carried.add(0.5 * m[p] * (vx[p] * vx[p] + vy[p] * vy[p] + vz[p] * vz[p]) + m[p] * e[p] -
                m[p] * (g.x() * x[p] + g.y() * y[p] + g.z() * z[p]));
  }
  if (std::find(leaving.begin(), leaving.end(), std::uint8_t{1}) == leaving.end()) return;
  P.remove_if(leaving);
  // On several ranks one rank may lose all its particles; finish_step checks the total.
  if (P.size() == 0 && !s.dist()) {
    throw NumericalError("every particle has left through the outflow boundaries", 0, s.clock.step);
  }
  s.sums.carried = carried;  // booked in finish_step, summed over the ranks
  // The internal energy reported with this step is the sum made at the end of the previous one
  // (internal_next), which still holds the departed particles: without this their internal
  // energy would count twice in this step's budget, once there and once in `carried` (a
  // single-row spike of the energy error, +0.3 to +0.5 % in the lab impact), and drop out of the
  // internal sum one row later. Kinetic and potential energy are dropped from this step's sums
  // (drop_departed), so all three leave the budget in the step that books them as outflow.
  s.sums.carried_internal = carried_internal;
  drop_departed(s.scratch, leaving);
}

}  // namespace

Stage advance_positions_stage(State& s) {
  return {"advance_positions", {{}, kDisplacement}, {kPosition, kDisplacement}, [&s] {
            advance_positions(s);
          }};
}

Stage outflow_stage(State& s) {
  return {"outflow", {{}, 0}, {all_fields(), kBudget}, [&s] { outflow(s); }};
}

}  // namespace shatter::mpm
