// This rank's energy sums of the step (kinetic at t^n, the kinetic energy the P2G transferred,
// potential, internal at t^{n+1}), exact; finish_step combines them over the ranks and books
// them.

#include <algorithm>
#include <array>

#include "mpm/loops.hpp"
#include "mpm/stages/stages.hpp"
#include "mpm/state.hpp"

namespace shatter::mpm {
namespace {

void energy(State& s) {
  ParticleStore& P = s.particles;
  const Scratch& sc = s.scratch;
  const auto m = P.col(Field::mass), e = P.col(Field::energy);
  // One pass for both kinetic sums; kinetic_transferred keeps the particles outflow removed
  // (their P2G momentum is on the nodes the unresolved sum took), so it may be longer.
  const std::size_t nk = sc.kinetic.size(), nt = sc.kinetic_transferred.size();
  using Pair = std::array<parallel::ExactSum, 2>;
  const Pair both = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, std::max(nk, nt), kParticleGrain), Pair{},
      [&](const tbb::blocked_range<std::size_t>& r, Pair acc) {
        for (std::size_t p = r.begin(); p < r.end(); ++p) {
          if (p < nk) acc[0].add(sc.kinetic[p]);
          if (p < nt) acc[1].add(sc.kinetic_transferred[p]);
        }
        return acc;
      },
      [](Pair a, const Pair& b) {
        a[0].add(b[0]);
        a[1].add(b[1]);
        return a;
      });
  s.sums.kinetic = both[0];
  s.sums.transferred = both[1];
  s.sums.potential = exact_sum(sc.potential.size(), [&](std::size_t p) { return sc.potential[p]; });
  s.sums.internal = exact_sum(P.size(), [&](std::size_t p) { return m[p] * e[p]; });
}

}  // namespace

Stage energy_stage(State& s) {
  return {"energy", {FieldSet{Field::mass, Field::energy}, kMechanical}, {{}, kBudget}, [&s] {
            energy(s);
          }};
}

}  // namespace shatter::mpm
