// Rigid-body kinematics of labelled fragments (MPM paper Eq. 20) and the equivalent ellipsoid.

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "fracture/cell_grid.hpp"
#include "fracture/rings.hpp"
#include "shatter/fracture/fragments.hpp"

namespace shatter {
namespace {

// omega = J^-1 L (Eq. 20) through the eigen-decomposition of J, inverting only the directions
// with non-negligible inertia: a fragment of one point or of collinear points has a singular J
// and no spin about the degenerate axes (the pseudo-inverse gives the minimum-norm omega).
Eigen::Vector3d solve_spin(const Eigen::Matrix3d& inertia, const Eigen::Vector3d& l) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(inertia);
  const Eigen::Vector3d lambda = eig.eigenvalues();
  const double tol = 1.0e-12 * std::max(lambda.cwiseAbs().maxCoeff(), 0.0);
  Eigen::Vector3d omega = Eigen::Vector3d::Zero();
  for (int a = 0; a < 3; ++a) {
    if (lambda[a] > tol && lambda[a] > 0.0) {
      const Eigen::Vector3d q = eig.eigenvectors().col(a);
      omega += (q.dot(l) / lambda[a]) * q;
    }
  }
  return omega;
}

// Semi-axes of the uniform ellipsoid with the same mass and principal moments: for semi-axes
// a >= b >= c the moments are M(b^2+c^2)/5 <= M(a^2+c^2)/5 <= M(a^2+b^2)/5.
std::array<double, 3> ellipsoid_axes(const Eigen::Matrix3d& inertia, double mass) {
  Eigen::Vector3d lambda =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(inertia, Eigen::EigenvaluesOnly).eigenvalues();
  const double f = 5.0 / (2.0 * mass);
  const double a2 = f * (lambda[1] + lambda[2] - lambda[0]);
  const double b2 = f * (lambda[0] + lambda[2] - lambda[1]);
  const double c2 = f * (lambda[0] + lambda[1] - lambda[2]);
  return {std::sqrt(std::max(a2, 0.0)), std::sqrt(std::max(b2, 0.0)), std::sqrt(std::max(c2, 0.0))};
}

// The particle columns the kinematics reads, visited in id order (`order`) so that the
// catalogue is bit-identical for any storage order.
struct Points {
  std::span<const double> x, y, z, vx, vy, vz, mass, vol0, rho;
  std::vector<std::uint32_t> order;

  explicit Points(const ParticleStore& store)
      : x(store.col(Field::x)),
        y(store.col(Field::y)),
        z(store.col(Field::z)),
        vx(store.col(Field::vx)),
        vy(store.col(Field::vy)),
        vz(store.col(Field::vz)),
        mass(store.col(Field::mass)),
        vol0(store.col(Field::volume0)),
        rho(store.has(Field::rho) ? store.col(Field::rho) : std::span<const double>{}),
        order(fracture::canonical_order(
            store.has(IField::id) ? store.col(IField::id) : std::span<const std::int64_t>{},
            store.size())) {}

  double volume(std::size_t p) const {
    return !rho.empty() && rho[p] > 0.0 ? mass[p] / rho[p] : vol0[p];
  }
  Eigen::Vector3d position(std::size_t p) const { return {x[p], y[p], z[p]}; }
  Eigen::Vector3d velocity(std::size_t p) const { return {vx[p], vy[p], vz[p]}; }
};

// Pass 1: m_f, m_f x_fc and P_f (Eq. 20), then x_fc and v_f; the catalogue's total and dust
// masses; and each fragment's first point in id order (`first_seen`, for canonical ranks).
void sum_mass_and_momentum(const Points& pts, const std::vector<std::int64_t>& labels,
                           std::vector<Fragment>& frags, std::vector<std::size_t>& first_seen,
                           FragmentCatalogue& cat) {
  for (std::size_t k = 0; k < pts.order.size(); ++k) {
    const std::size_t p = pts.order[k];
    cat.total_mass += pts.mass[p];
    if (labels[p] < 0) {
      cat.dust_mass += pts.mass[p];
      continue;
    }
    const auto l = static_cast<std::size_t>(labels[p]);
    Fragment& f = frags[l];
    first_seen[l] = std::min(first_seen[l], k);
    f.particles += 1;
    f.mass += pts.mass[p];
    f.centre += pts.mass[p] * pts.position(p);
    f.momentum += pts.mass[p] * pts.velocity(p);
    f.volume += pts.volume(p);
  }
  for (auto& f : frags) {
    if (f.mass > 0.0) {
      f.centre /= f.mass;
      f.velocity = f.momentum / f.mass;
    }
  }
}

// Pass 2: L_fc = sum x_p x m_p v_p - x_fc x P_f, summed as sum m_p r x u with r, u relative to
// the centre of mass (the same quantity, without the cancellation of two large terms), and J_c;
// then omega (Eq. 20) and the equivalent ellipsoid.
void sum_spin_and_shape(const Points& pts, const std::vector<std::int64_t>& labels,
                        std::vector<Fragment>& frags) {
  std::vector<Eigen::Matrix3d> self_inertia(frags.size(), Eigen::Matrix3d::Zero());
  for (const std::size_t p : pts.order) {
    if (labels[p] < 0) continue;
    const auto l = static_cast<std::size_t>(labels[p]);
    Fragment& f = frags[l];
    const double m = pts.mass[p];
    const Eigen::Vector3d r = pts.position(p) - f.centre;
    const Eigen::Vector3d u = pts.velocity(p) - f.velocity;
    f.angular_momentum += m * r.cross(u);
    f.inertia += m * (r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose());
    // A point stands for a cube of its volume (side s, own moment m s^2 / 6); used for the
    // shape only, since particles carry no spin of their own.
    const double s = std::cbrt(pts.volume(p));
    self_inertia[l] += (m * s * s / 6.0) * Eigen::Matrix3d::Identity();
  }
  for (std::size_t l = 0; l < frags.size(); ++l) {
    Fragment& f = frags[l];
    if (f.particles == 0) continue;
    f.omega = solve_spin(f.inertia, f.angular_momentum);
    f.axes = ellipsoid_axes(f.inertia + self_inertia[l], f.mass);
  }
}

// r-z (issue 31): the fragment is the body of revolution its rings sweep about z. By symmetry its
// centre lies on the axis, its momentum is along z (a ring's radial momenta cancel round it) and,
// v_theta being zero, it has no spin. The inertia about the centre is the revolved mass's: a ring
// of mass m, radius r, height dz above the centre has J_zz = m r^2, J_xx = J_yy = m (r^2/2 + dz^2).
// The equivalent ellipsoid adds each ring's cross-section as a square of side sqrt(A), as the 3-D
// path adds each point's cube. touches_axis: a ring closer to the axis than one point spacing
// (sqrt of the mean cross-section; the lattice's first ring sits half a spacing off the axis).
void revolve(const Points& pts, const ParticleStore& store, const std::vector<std::int64_t>& labels,
             std::vector<Fragment>& frags) {
  const std::vector<double> area = fracture::ring_areas(store);
  double total_area = 0.0;
  for (const std::size_t p : pts.order) total_area += area[p];
  const double spacing =
      std::sqrt(total_area / static_cast<double>(std::max<std::size_t>(pts.order.size(), 1)));
  std::vector<Eigen::Matrix3d> self_inertia(frags.size(), Eigen::Matrix3d::Zero());
  for (auto& f : frags) {
    f.centre = {0.0, 0.0, f.centre.z()};
    f.momentum = {0.0, 0.0, f.momentum.z()};
    f.velocity = {0.0, 0.0, f.velocity.z()};
    f.angular_momentum.setZero();
    f.omega.setZero();
    f.inertia.setZero();
    f.r_min = std::numeric_limits<double>::infinity();
    f.r_max = 0.0;
  }
  for (const std::size_t p : pts.order) {
    if (labels[p] < 0) continue;
    const auto l = static_cast<std::size_t>(labels[p]);
    Fragment& f = frags[l];
    const double m = pts.mass[p], r = pts.x[p], dz = pts.z[p] - f.centre.z();
    f.inertia += m * Eigen::Vector3d(0.5 * r * r + dz * dz, 0.5 * r * r + dz * dz, r * r)
                         .asDiagonal()
                         .toDenseMatrix();
    self_inertia[l] += (m * area[p] / 6.0) * Eigen::Matrix3d::Identity();
    f.r_min = std::min(f.r_min, r);
    f.r_max = std::max(f.r_max, r);
  }
  for (std::size_t l = 0; l < frags.size(); ++l) {
    Fragment& f = frags[l];
    if (f.particles == 0) continue;
    f.axes = ellipsoid_axes(f.inertia + self_inertia[l], f.mass);
    f.touches_axis = f.r_min < spacing;
  }
}

// The fragments into the catalogue, largest first (equal masses by the first particle in id
// order, so ranks are canonical), and the labels renumbered to those ranks.
void rank_fragments(const std::vector<Fragment>& frags, const std::vector<std::size_t>& first_seen,
                    std::vector<std::int64_t>& labels, FragmentCatalogue& cat) {
  const std::size_t nf = frags.size();
  std::vector<std::size_t> rank(nf);
  std::iota(rank.begin(), rank.end(), std::size_t{0});
  std::sort(rank.begin(), rank.end(), [&](std::size_t a, std::size_t b) {
    if (frags[a].mass != frags[b].mass) return frags[a].mass > frags[b].mass;
    return first_seen[a] < first_seen[b];
  });
  std::vector<std::int64_t> new_id(nf, -1);
  for (std::size_t r = 0; r < nf; ++r) {
    if (frags[rank[r]].particles == 0) continue;
    new_id[rank[r]] = static_cast<std::int64_t>(cat.fragments.size());
    cat.fragments.push_back(frags[rank[r]]);
    cat.fragments.back().id = new_id[rank[r]];
  }
  for (auto& l : labels)
    if (l >= 0) l = new_id[static_cast<std::size_t>(l)];
}

}  // namespace

FragmentCatalogue fragment_kinematics(const ParticleStore& store, std::vector<std::int64_t>& labels,
                                      bool axisymmetric) {
  const std::size_t n = store.size();
  if (labels.size() != n) throw std::invalid_argument("fragment kinematics: label count mismatch");
  const Points pts(store);
  std::int64_t count = 0;
  for (std::int64_t l : labels) count = std::max(count, l + 1);
  const auto nf = static_cast<std::size_t>(count);
  std::vector<Fragment> frags(nf);
  std::vector<std::size_t> first_seen(nf, n);
  FragmentCatalogue cat;
  sum_mass_and_momentum(pts, labels, frags, first_seen, cat);
  sum_spin_and_shape(pts, labels, frags);
  if (axisymmetric) revolve(pts, store, labels, frags);
  cat.axisymmetric = axisymmetric;
  rank_fragments(frags, first_seen, labels, cat);
  return cat;
}

std::vector<CumulativePoint> cumulative_mass_distribution(const FragmentCatalogue& cat) {
  std::vector<CumulativePoint> out;
  std::size_t count = 0;
  double cumulative = 0.0;
  for (const auto& f : cat.fragments) {  // already sorted by decreasing mass
    ++count;
    cumulative += f.mass;
    if (!out.empty() && out.back().mass == f.mass) {
      out.back().count = count;
      out.back().cumulative_mass = cumulative;
    } else {
      out.push_back({f.mass, count, cumulative});
    }
  }
  return out;
}

}  // namespace shatter
