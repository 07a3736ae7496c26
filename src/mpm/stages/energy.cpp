// This rank's energy sums of the step (kinetic at t^n, potential, internal at t^{n+1}; the
// kinetic energy the P2G transferred is summed by G2P), exact; finish_step combines them over
// the ranks and books them.

#include "mpm/loops.hpp"
#include "mpm/stages/stages.hpp"
#include "mpm/state.hpp"

namespace shatter::mpm {
namespace {

void energy(State& s) {
  ParticleStore& P = s.particles;
  const Scratch& sc = s.scratch;
  const auto m = P.col(Field::mass), e = P.col(Field::energy);
  // (The transferred kinetic energy, StepSums::transferred, is summed by G2P.)
  // (The kinetic energy at t^n, StepSums::kinetic, is summed by G2P over the points that stay.)
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
