#pragma once
// Boundary conditions on grid planes (ISSUE engine item 7) and the nodal momentum update
// (App. A.2 steps 2-4 and 6-7).

#include <array>
#include <cstdint>
#include <vector>

#include "shatter/engine/config.hpp"
#include "shatter/grid/sparse_grid.hpp"
#include "shatter/parallel/exact_sum.hpp"

namespace shatter::engine {

class Boundaries {
 public:
  // Throws std::invalid_argument if a face with a condition does not lie on a grid plane.
  Boundaries(const Domain& domain, double cell_size);

  enum MirrorMode { kMassMomentumForce, kMomentum };

  bool has_outflow() const;
  bool outside_outflow(const Vec3& x) const;

  // Symmetry planes: makes the nodal fields mirror-symmetric about each plane. Contributions that
  // particles made to nodes beyond the plane are what their mirror images would have made to the
  // partner nodes, so they are folded in (normal components with flipped sign); the ghost nodes
  // then take the mirror of the completed field. A half model then sees exactly the field of the
  // full symmetric model.
  void mirror(SparseGrid& grid, MirrorMode mode) const;
  // Only the second half of mirror(): ghost nodes take the image of their partners' p* and f*
  // arrays (velocity and acceleration after integrate()). Used after the contact correction,
  // which treats a ghost and its partner separately (their blocks need not meet the same bodies).
  void mirror_ghosts(SparseGrid& grid) const;

  // Steps 2-4: gravity, constraints on momentum and force, P^{n+1/2} = P^{n-1/2} + F dt^n
  // (Eq. 27). Leaves the nodal acceleration F/M in f* and velocity P^{n+1/2}/M in p*. Returns the
  // kinetic energy the constraints removed.
  // The kinetic energy the constraints removed is summed exactly (parallel::ExactSum), so it does
  // not depend on the block order; `counted` (one flag per block), when given, limits the sum
  // to the blocks this rank owns (ghost blocks hold copies of other ranks' nodes).
  // `exact`, when given, also receives the exact sum (to be combined across ranks).
  double integrate(SparseGrid& grid, const Vec3& gravity, double dt, double empty_mass,
                   const std::vector<std::uint8_t>* counted = nullptr,
                   parallel::ExactSum* exact = nullptr) const;

  // Steps 6-7: constraints on the remapped momentum, then v_I = P_I / M_I in p*. Returns the
  // nodal kinetic energy the constraints removed (a diagnostic: no particle velocity changes).
  double velocities(SparseGrid& grid, double empty_mass,
                    const std::vector<std::uint8_t>* counted = nullptr) const;

  bool constrained() const { return count_ > 0; }
  // Zeroes the constrained components of (x, y, z) at global node `node` (steps 2-3).
  void constrain(const std::int64_t node[3], double& x, double& y, double& z) const;

 private:
  void mirror_impl(SparseGrid& grid, MirrorMode mode, bool fold) const;
  struct Plane {
    int axis;
    int side;            // -1: the domain's low face (material at i >= index), +1: high face
    std::int64_t index;  // node index of the plane along axis
    BoundaryKind kind;
  };
  std::array<Plane, 6> planes_{};
  int count_ = 0;
  Domain domain_;
};

}  // namespace shatter::engine
