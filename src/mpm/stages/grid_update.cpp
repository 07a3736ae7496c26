// App. A.2 steps 2-4: boundary conditions and the momentum update on the grid (Eq. 27), the
// contact correction where bodies meet, and the unresolved kinetic energy of the scatter.

#include "mpm/loops.hpp"
#include "mpm/stages/stages.hpp"
#include "mpm/state.hpp"

namespace shatter::mpm {
namespace {

// -sum_I |p_I|^2 / (2 m_I) over the nodes of the step's force-carrying P2G, p_I and m_I the
// lumped momentum sum_p m_p N_I(x_p) v_p and mass sum_p m_p N_I(x_p) (Eqs. 29, 32), added to
// the particles' sum_p m_p |v_p|^2/2 of the same velocities (the energy stage) it is the kinetic
// energy the grid does not represent: >= 0, since with sum_I N_I(x_p) = 1 the nodal velocity
// p_I/m_I is a mass-weighted mean of the v_p (Cauchy-Schwarz: |p_I|^2 <= m_I sum_p m_p N_I
// |v_p|^2). It is exactly the kinetic energy the grid velocity lacks, and so the least one PIC
// transfer v_p <- sum_I N_I p_I/m_I takes away (the gather loses more: sum_p m_p |S V|^2/2 <=
// sum_I m_I |V_I|^2/2 by the same argument). Zero for a rigid translation. Body copies hold each
// body's own field where bodies meet (the shared nodes there are empty), so the sum is over every
// body's field. One rank: the raw scatter, before the mirror of symmetry/fixed planes folds
// images in, so the nodes beyond a plane hold only the real particles' own weights and nothing
// is counted twice. Several ranks: the halo exchange sums each node on its owner, from the same
// complete sums before the same mirror, so the value is the one process's, bit for bit.
void unresolved_kinetic(State& s) {
  if (s.dist()) return;  // summed in the halo exchange, before its mirror
  auto& N = s.grid.nodes();
  s.sums.unresolved = node_unresolved(
      s.grid.blocks(), [](std::uint32_t) { return true; },
      [&](std::uint32_t b, int f) {
        double* const a[4] = {N.mass.data(), N.px.data(), N.py.data(), N.pz.data()};
        return a[f] + std::size_t{b} * SparseGrid::kBlockNodes;
      });
}

void grid_update(State& s) {
  const double dt_kick = 0.5 * (s.clock.dt_prev + s.dt_step);  // leapfrog dt^n (Fig. 16)
  // The resolved kinetic energy of the P2G, before the mirror folds images in and before the
  // boundary conditions and the momentum update change the nodes.
  unresolved_kinetic(s);
  // (several ranks: the owners mirrored the halo blocks in the halo exchange)
  if (!s.dist()) s.boundaries.mirror(s.grid, Boundaries::kMassMomentumForce);
  s.boundaries.integrate(s.grid, s.config.gravity, dt_kick, s.empty_mass,
                         s.dist() ? &s.ranks.halo.owned : nullptr, &s.sums.removed);
  // Driven bodies' nodes take the prescribed velocity before contact sees them (driven.hpp).
  if (s.driven) s.energy.boundary_work -= s.driven->constrain(s.grid, dt_kick);
  if (s.grid.has_copies()) {
    // Contact after the momentum update (end of step 4): G2P hands the particles the corrected
    // velocity and acceleration. What the correction takes out of the nodal kinetic energy is
    // not booked: it is not what the FLIP particles lose (booking it gave +33% error in the lab
    // impact and +400% in the contact test), so EnergyBudget::error() shows the contact's net
    // dissipation (docs/verification.md, contact).
    s.contact->resolve(s.grid, s.boundaries, dt_kick, s.empty_mass);
    // A ghost node and its partner across a symmetry plane (or fixed wall) need not lie in
    // blocks that meet the same bodies, so the correction may treat them differently; the
    // ghosts take the image of the corrected field again.
    s.boundaries.mirror_ghosts(s.grid);
  }
  // The kinetic energy a constraint takes out of the nodal momentum leaves the particles only
  // when they take the grid velocity (APIC). FLIP particles keep their own velocity and feel a
  // wall only through the constrained acceleration, so there is nothing to book: an ideal wall
  // does no work, and booking the nodal loss made a clamped bar that keeps its energy report a
  // 2.4% "boundary work" drift (scenes/verification/vibrating-bar.toml). The same holds for the
  // share of the grid velocity that PIC, XPIC and the FLIP/PIC blend hand the particles
  // (booked in finish_step, summed over the ranks).
}

}  // namespace

Stage grid_update_stage(State& s) {
  return {"grid_update", {{}, kClock | kBlocks}, {{}, kGrid | kBudget}, [&s] { grid_update(s); }};
}

}  // namespace shatter::mpm
