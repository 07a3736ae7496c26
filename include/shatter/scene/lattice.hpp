#pragma once
// Filling a body with material points on a lattice aligned with the background grid (MPM paper
// Sec. 4.1.1: 2 x 2 x 2 points per cell when the spacing is half the cell size).

#include <cstddef>
#include <functional>
#include <limits>
#include <vector>

#include <Eigen/Core>

#include "shatter/scene/shapes.hpp"

namespace shatter::scene {

struct LatticeFill {
  std::vector<Vec3> points;
  double volume = 0.0;  // volume of shape ∩ kept half-space, measured on the lattice cells
  // Each point's volume where they differ (the axisymmetric fill: each point is a ring); empty
  // when every point has volume / points.
  std::vector<double> volumes;
};

// Points at R ((i + 1/2) s, (j + 1/2) s, (k + 1/2) s) that lie inside `shape`, x fastest, with R
// the body's lattice rotation about the origin (`lattice_rotation`; the identity by default, the
// MPM paper's lattice aligned with the grid, Sec. 4.1.1). With `clip_axis` in {0, 1, 2}, only
// points with a positive coordinate on that axis are kept (the half model of a symmetry plane
// through the origin; the plane is a lattice-cell face, so the mirror image of the kept points is
// exactly the dropped ones; R must then turn about that axis only, which the scene checks). The
// volume is the sum over lattice cells of the fraction inside the shape, sub-sampled where a cell
// straddles its surface.
LatticeFill fill_lattice(const Shape& shape, double spacing, int clip_axis = -1,
                         const Eigen::Matrix3d& rotation = Eigen::Matrix3d::Identity());

// The points fill_lattice would create, counted without storing them (`shatter check`): their
// number and the bounds of their positions. Same inside test, so the count is the same.
struct LatticeCount {
  std::size_t points = 0;
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 hi = Vec3::Constant(-std::numeric_limits<double>::infinity());
};
LatticeCount count_lattice(const Shape& shape, double spacing, int clip_axis = -1,
                           const Eigen::Matrix3d& rotation = Eigen::Matrix3d::Identity());

// Calls visit(point) for every point fill_lattice would create, in the same order.
void for_each_lattice_point(const Shape& shape, double spacing, int clip_axis,
                            const std::function<void(const Vec3&)>& visit,
                            const Eigen::Matrix3d& rotation = Eigen::Matrix3d::Identity());

// The axisymmetric (r-z) fill (SolverConfig::Geometry::axisymmetric; src/scene/lattice_rz.cpp):
// points at ((i + 1/2) s, 0, (k + 1/2) s), i >= 0, in the half-plane y = 0, r = x > 0, that lie
// inside `shape` (a body of revolution about the z axis, which the scene checks). Each point
// stands for the ring its s x s cell sweeps about the axis, of volume 2 pi r s^2; the volumes
// are scaled so that they add up to the body's volume of revolution, measured on the cells
// (sub-sampled where a cell straddles the surface), as fill_lattice's equal volumes are.
LatticeFill fill_lattice_rz(const Shape& shape, double spacing);
void for_each_lattice_point_rz(const Shape& shape, double spacing,
                               const std::function<void(const Vec3&)>& visit);

}  // namespace shatter::scene
