// The r-z engine's preconditions (axisymmetric.hpp). The scene refuses these with the key and
// its line (src/scene/parse_solver.cpp, src/scene/axisymmetric_check.cpp); this is the engine's
// own guard for callers that build a SolverConfig by hand.

#include "mpm/axisymmetric.hpp"

#include <stdexcept>
#include <string>

#include <fmt/format.h>

namespace shatter::mpm {
namespace {

[[noreturn]] void refuse(const std::string& what) {
  throw std::invalid_argument("solver.geometry = \"axisymmetric\": " + what);
}

void check_options(const SolverConfig& c, bool several_ranks) {
  if (c.shape == ShapeKind::ugimp) {
    // Nairn & Guilkey (2015, IJNME 101) show that uGIMP in r-z needs shape functions
    // integrated with the radial weight over the particle domain; the 3-D ones are not those.
    refuse(
        "solver.shape \"ugimp\" is not supported in r-z (it needs the r-weighted GIMP shapes "
        "of Nairn & Guilkey 2015); use \"linear\" or \"bspline2\"");
  }
  if (c.transfer != TransferKind::flip) {
    refuse(
        fmt::format("solver.transfer \"{}\" is not supported in r-z yet (only \"flip\": "
                    "APIC's affine momentum has no hoop term, and the filters are untested)",
                    name_of(c.transfer)));
  }
  if (c.contact.kind == ContactKind::multi_field) {
    refuse(
        "solver.contact \"multi_field\" is not supported in r-z yet (its mass gradients "
        "are taken with 3-D stencils)");
  }
  if (c.self_gravity.self) refuse("gravity.self is not supported in r-z");
  if (c.gravity.x() != 0.0 || c.gravity.y() != 0.0) {
    refuse("solver.gravity must lie along z (the axis of symmetry)");
  }
  if (several_ranks) refuse("runs on one MPI rank only (r-z blocks are not decomposed yet)");
  if (c.domain.faces[0] != BoundaryKind::symmetry || c.domain.lo.x() != 0.0) {
    refuse("the axis r = 0 must be the symmetry face x_lo at x = 0 (the scene sets it)");
  }
}

}  // namespace

void check_axisymmetric(const SolverConfig& c, const ParticleStore& P, bool several_ranks) {
  if (c.geometry != Geometry::axisymmetric) return;
  check_options(c, several_ranks);
  const auto x = P.col(Field::x), y = P.col(Field::y);
  const auto vy = P.col(Field::vy);
  for (std::size_t p = 0; p < P.size(); ++p) {
    // r_p > 0: the hoop terms divide by it; y = 0 and v_y = 0: the r-z half-plane, no torsion.
    if (!(x[p] > 0.0) || y[p] != 0.0 || vy[p] != 0.0) {
      refuse(
          fmt::format("point {} at (x, y) = ({}, {}) m with v_y = {} m/s: every point must "
                      "lie at y = 0, x > 0 with v_y = 0",
                      p, x[p], y[p], vy[p]));
    }
  }
}

}  // namespace shatter::mpm
