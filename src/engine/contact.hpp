#pragma once
// Multi-velocity-field contact between bodies (issue 11 item 3; docs/architecture.md "Contact").
// Where the stencils of several bodies meet, SparseGrid keeps one velocity field per body (body
// copies of the block). After the nodal momentum update (App. A.2 step 4) and again after the
// MUSL remap (step 6), every pair of body fields at a node is corrected as in Bardenhagen et al.
// (2000, Eqs. 11-14; 2001): the pair moves together along the contact normal while it approaches
// and slides with Coulomb friction, and is left alone while it separates (no tension across an
// interface). Each correction is equal and opposite, so nodal momentum is conserved.

#include <cstdint>
#include <vector>

#include "engine/boundaries.hpp"
#include "shatter/engine/config.hpp"
#include "shatter/grid/sparse_grid.hpp"

namespace shatter::engine {

class Contact {
 public:
  // `bodies`: one more than the largest body id.
  Contact(const ContactConfig& config, std::int64_t bodies);

  double friction(std::int64_t a, std::int64_t b) const {
    return mu_[static_cast<std::size_t>(a * n_ + b)];
  }

  // Corrects the body fields at every node where several meet. The grid holds velocities in p*
  // and, when dt > 0 (after step 4), accelerations in f*, which take the correction / dt so that
  // the particles feel it (G2P). Constraints of `bc` are imposed again on corrected nodes.
  // Returns the nodal kinetic energy the corrections removed (inelastic normal impact of the
  // node pair and friction; >= 0).
  double resolve(SparseGrid& grid, const Boundaries& bc, double dt, double empty_mass) const;

 private:
  std::int64_t n_ = 0;
  std::vector<double> mu_;  // n_ x n_, symmetric
};

}  // namespace shatter::engine
