// App. A.2 step 6 (MUSL): the updated particle momentum back to the grid
// (remap), then, after the exchange of its node sums on several ranks
// (halo_remap, src/parallel/mpm/halo.cpp), the nodal velocities the strain rate
// (step 7) is built from (remap_velocity).

#include <algorithm>

#include "mpm/loops.hpp"
#include "mpm/stages/stages.hpp"
#include "mpm/state.hpp"

namespace shatter::mpm {
namespace {

// The first body-copy node: copies follow the shared blocks
// (SparseGrid::assign).
std::size_t copies_from(const State& s) {
  return s.grid.shared_blocks() * SparseGrid::kBlockNodes;
}

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

// The scatter of the remap: where bodies meet, the strain rate takes the step-4
// velocities of the body fields (USL, the velocities the contact correction and
// the forces acted on), not the remapped ones: FLIP particle velocities
// remapped to two body fields disagree with the corrected fields, and the
// strain rate built from them made stress that no kinetic energy paid for. A
// sphere bouncing off a plate left with +31% energy; two cubes meeting head-on,
// with the contact correction applied to the remapped fields instead, with 2.2x
// (docs/verification.md, contact). Keeping the step-4 velocities there never
// created energy in any test (as APIC, which has no remap): they are set aside
// here and put back by remap_velocity.
template <class Shape>
void remap_scatter(State& s) {
  if (s.grid.has_copies()) keep_copies(s.grid.nodes(), copies_from(s), s.scratch.step4_velocity);
  p2g<Shape>(s, false);
}

// After the scatter (and, on several ranks, its exchange): the remapped nodal
// velocities with the boundary conditions. They only feed the strain rate
// (MUSL); no particle velocity changes.
void remap_velocity(State& s) {
  if (!s.dist()) s.boundaries.mirror(s.grid, Boundaries::kMomentum);
  s.boundaries.velocities(s.grid, s.empty_mass);
  if (s.grid.has_copies()) {
    put_back_copies(s.grid.nodes(), copies_from(s), s.scratch.step4_velocity);
  }
}

// What the remap reads and writes. Its stages (scatter, exchange, velocities)
// each declare all of it, so every other stage is ordered against each of them
// as against the remap as a whole.
constexpr Access kRemapReads{kGeometry | kVelocity | FieldSet{Field::mass}, kBlocks | kBudget};
constexpr Access kRemapWrites{{}, kGrid | kBudget};

}  // namespace

template <class Shape>
Stage remap_stage(State& s) {
  return {"remap", kRemapReads, kRemapWrites, [&s] { remap_scatter<Shape>(s); }};
}

Stage remap_velocity_stage(State& s) {
  return {"remap_velocity", kRemapReads, kRemapWrites, [&s] { remap_velocity(s); }};
}

#define SHATTER_INSTANTIATE(S) template Stage remap_stage<S>(State & s);
SHATTER_FOR_EACH_SHAPE(SHATTER_INSTANTIATE)

}  // namespace shatter::mpm
