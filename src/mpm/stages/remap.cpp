// App. A.2 step 6 (MUSL): the updated particle momentum back to the grid, and the nodal
// velocities the strain rate (step 7) is built from.

#include <algorithm>

#include "mpm/loops.hpp"
#include "mpm/stages/stages.hpp"
#include "mpm/state.hpp"
#include "parallel/mpm/exchanges.hpp"

namespace shatter::mpm {
namespace {

// The body-copy node momenta (nodes from g0 on) into `kept`, or back from it.
void keep_copies(SparseGrid::Nodes& N, std::size_t g0, std::vector<double>& kept) {
  const auto n = static_cast<std::ptrdiff_t>(N.px.size() - g0);
  kept.resize(3 * static_cast<std::size_t>(n));
  const auto at = kept.begin();
  std::copy(N.px.begin() + static_cast<std::ptrdiff_t>(g0), N.px.end(), at);
  std::copy(N.py.begin() + static_cast<std::ptrdiff_t>(g0), N.py.end(), at + n);
  std::copy(N.pz.begin() + static_cast<std::ptrdiff_t>(g0), N.pz.end(), at + 2 * n);
}
void put_back_copies(SparseGrid::Nodes& N, std::size_t g0, const std::vector<double>& kept) {
  const auto n = static_cast<std::ptrdiff_t>(N.px.size() - g0);
  const auto at = kept.begin();
  std::copy(at, at + n, N.px.begin() + static_cast<std::ptrdiff_t>(g0));
  std::copy(at + n, at + 2 * n, N.py.begin() + static_cast<std::ptrdiff_t>(g0));
  std::copy(at + 2 * n, at + 3 * n, N.pz.begin() + static_cast<std::ptrdiff_t>(g0));
}

template <class Shape>
void remap(State& s) {
  // Where bodies meet, the strain rate takes the step-4 velocities of the body fields (USL, the
  // velocities the contact correction and the forces acted on), not the remapped ones: FLIP
  // particle velocities remapped to two body fields disagree with the corrected fields, and the
  // strain rate built from them made stress that no kinetic energy paid for. A sphere bouncing
  // off a plate left with +31% energy; two cubes meeting head-on, with the contact correction
  // applied to the remapped fields instead, with 2.2x (docs/verification.md, contact). Keeping
  // the step-4 velocities there never created energy in any test (as APIC, which has no remap).
  const bool contact_nodes = s.grid.has_copies();
  const std::size_t g0 = s.grid.shared_blocks() * SparseGrid::kBlockNodes;
  auto& N = s.grid.nodes();
  if (contact_nodes) keep_copies(N, g0, s.scratch.step4_velocity);
  p2g<Shape>(s, false);
  if (s.dist()) parallel::halo_reduce(s, parallel::kMomentumExchange);
  if (!s.dist()) s.boundaries.mirror(s.grid, Boundaries::kMomentum);
  // The remapped velocities only feed the strain rate (MUSL); no particle velocity changes here.
  s.boundaries.velocities(s.grid, s.empty_mass);
  if (contact_nodes) put_back_copies(N, g0, s.scratch.step4_velocity);
}

}  // namespace

template <class Shape>
Stage remap_stage(State& s) {
  return {"remap",
          {kGeometry | kVelocity | FieldSet{Field::mass}, kBlocks | kBudget},
          {{}, kGrid | kBudget},
          [&s] { remap<Shape>(s); }};
}

#define SHATTER_INSTANTIATE(S) template Stage remap_stage<S>(State & s);
SHATTER_FOR_EACH_SHAPE(SHATTER_INSTANTIATE)

}  // namespace shatter::mpm
