#pragma once
// Multi-velocity-field contact between bodies (issue 11 item 3; docs/architecture.md "Contact").
// Where the stencils of several bodies meet, SparseGrid keeps one velocity field per body (body
// copies of the block). After the nodal momentum update (App. A.2 step 4) every pair of body
// fields at a node is corrected as in Bardenhagen et al. (2000; 2001): the pair moves together
// along the contact normal while it approaches and slides with Coulomb friction, and is left
// alone while it separates (no tension across an interface). Each correction is equal and
// opposite, so nodal momentum is conserved. The correction runs twice (Nairn et al. 2020): on
// the velocities the particles brought to the grid, changing only the nodal velocity, and on the
// updated velocities, also handed to the particles as an acceleration (Contact::resolve). (Why
// not again after the MUSL remap: see Simulation::remap.)

#include <cstdint>
#include <unordered_map>

#include "shatter/core/config.hpp"
#include "shatter/grid/sparse_grid.hpp"
#include "shatter/mpm/boundaries.hpp"

namespace shatter::mpm {

class Contact {
 public:
  explicit Contact(const ContactConfig& config);

  // Coulomb coefficient of a pair of body ids: the listed pair's, else the scene-wide one.
  // Memory grows with the listed pairs, not with the number of bodies (rubble piles).
  double friction(std::int64_t a, std::int64_t b) const {
    if (pairs_.empty()) return friction_;
    const auto it = pairs_.find(key(a, b));
    return it == pairs_.end() ? friction_ : it->second;
  }

  // Corrects the body fields at every node where several meet. The grid holds velocities in p*
  // and, when dt > 0 (after step 4), accelerations in f*. With dt > 0 a first pass corrects the
  // velocities before the update, p* - dt f*, in p* only; the second corrects p* and adds the
  // correction / dt to f* so that the particles feel it (G2P). Constraints of `bc` are imposed
  // again on corrected nodes.
  // Returns the nodal kinetic energy the corrections removed (inelastic normal impact of the
  // node pair and friction; >= 0).
  double resolve(SparseGrid& grid, const Boundaries& bc, double dt, double empty_mass) const;

 private:
  // resolve at node l of one meeting block: every pair of the body fields present, then the
  // constraints again; returns the kinetic energy removed there.
  double resolve_node(SparseGrid& grid, const SparseGrid::Meeting& mt, int l, const Boundaries& bc,
                      double dt, double empty_mass) const;
  static std::uint64_t key(std::int64_t a, std::int64_t b) {
    const auto lo = static_cast<std::uint64_t>(a < b ? a : b);
    const auto hi = static_cast<std::uint64_t>(a < b ? b : a);
    return (hi << 32) ^ lo;
  }
  double friction_ = 0.0;
  std::unordered_map<std::uint64_t, double> pairs_;
};

}  // namespace shatter::mpm
