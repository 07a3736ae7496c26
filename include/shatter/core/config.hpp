#pragma once
// Solver settings: everything the MUSL step needs that is not particle data.

#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "shatter/gravity/config.hpp"
#include "shatter/material/material_model.hpp"

namespace shatter {

class ParticleStore;
using Vec3 = Eigen::Vector3d;

// Shape functions (ISSUE engine item 4). uGIMP is the paper's choice (Sec. 2).
enum class ShapeKind : std::uint8_t { linear, ugimp, bspline2 };
constexpr std::string_view name_of(ShapeKind s) {
  return s == ShapeKind::linear ? "linear" : s == ShapeKind::ugimp ? "ugimp" : "bspline2";
}

// How velocity travels between particles and grid.
//  flip - the paper's MUSL step (App. A.2): a particle keeps its own velocity and adds the
//         interpolated grid acceleration; the new momentum is remapped to the grid (step 6)
//         before the strain update. Non-dissipative, but grid-invisible velocity noise is never
//         removed: under large deformation it feeds back through the moving particles and grows
//         (docs/verification.md, manufactured solution with G = 0.05).
//  apic - affine particle-in-cell (Jiang et al. 2015, "The affine particle-in-cell method"):
//         a particle takes the grid velocity and carries its gradient C_p, which restores the
//         affine part of the field that plain PIC would smooth away. Filters the noise, keeps
//         momentum exact; needs no remap (the grid velocity is already the particles'), so the
//         step has one transfer pass fewer, at 72 bytes per particle for C_p.
//  xpic - extended PIC of order m (Hammerquist & Nairn 2017, "A new method for material point
//         method particle updates that reduces noise and enhances stability", Comput. Methods
//         Appl. Mech. Engrg. 318, 724-738): the particle takes S (V*_m + a dt), where
//         V*_m = sum_{k=1..m} (-1)^{k+1} C(m,k) (S+ S)^{k-1} V^L is the lumped grid velocity
//         with the PIC filter's null-space projection applied m times (m - 1 extra
//         grid-particle-grid passes per step). XPIC(1) is PIC; m -> infinity is FLIP with the
//         null-space noise removed. SolverConfig::xpic_order sets m.
//  fmpm - approximate full-mass-matrix MPM of order k (Nairn & Hammerquist 2021, "Material
//         point method simulations using an approximate full mass matrix inverse", Comput.
//         Methods Appl. Mech. Engrg. 377, 113667; Nairn 2026, arXiv 2604.07307): the grid
//         velocity is v_F = sum_{i=0..k-1} (I - M_L^{-1} M_c)^i M_L^{-1} p^{n+1}, the order-k
//         series for the full mass matrix inverse applied to the updated grid momentum (k - 1
//         extra grid-particle-grid passes), and the particle takes v_p = S v_F and moves by
//         S v_F dt. FMPM(1) is PIC, bitwise. XPIC(k) applies the same series to the velocity at
//         the start of the step only and adds a dt unfiltered. SolverConfig::fmpm_order sets k.
// FLIP also takes SolverConfig::pic_fraction: v_p <- (1 - f) (v_p + S a dt) + f S v^{n+1}, the
// FLIP/PIC blend (Stomakhin et al. 2013 use f = 0.05); f = 0 is the paper's FLIP, bitwise.
// xpic and fmpm also take SolverConfig::filter_every = N: the filtered update on every N-th step
// only (steps N, 2N, ... counted from 1) and plain FLIP on the others (the "PeriodicXPIC"
// custom task of Nairn's NairnMPM/OSParticulas code; periodic FMPM(k) of Nairn 2026).
enum class TransferKind : std::uint8_t { flip, apic, xpic, fmpm };
constexpr std::string_view name_of(TransferKind t) {
  return t == TransferKind::flip   ? "flip"
         : t == TransferKind::apic ? "apic"
         : t == TransferKind::xpic ? "xpic"
                                   : "fmpm";
}

// How bodies meet on the grid (docs/architecture.md "Contact").
//  single_field - one velocity field shared by every body: the MPM paper's "non-slip" contact
//                 (Sec. 2): bodies stick and pull on each other across an interface.
//  multi_field  - one velocity field per body where several meet (Bardenhagen et al. 2000,
//                 2001; Huang et al. 2011): bodies push on each other only while they approach,
//                 with Coulomb friction; separating bodies are left alone.
enum class ContactKind : std::uint8_t { single_field, multi_field };
constexpr std::string_view name_of(ContactKind c) {
  return c == ContactKind::single_field ? "single_field" : "multi_field";
}

// Coulomb friction coefficient of one pair of bodies (IField::body ids), either order.
struct ContactPair {
  std::int64_t a = 0, b = 0;
  double friction = 0.0;
};

struct ContactConfig {
  ContactKind kind = ContactKind::single_field;
  double friction = 0.0;           // every pair not listed in `pairs`
  std::vector<ContactPair> pairs;  // the last entry naming a pair wins
  double coefficient(std::int64_t a, std::int64_t b) const {
    double mu = friction;
    for (const ContactPair& p : pairs) {
      if ((p.a == a && p.b == b) || (p.a == b && p.b == a)) mu = p.friction;
    }
    return mu;
  }
};

// Boundary condition on one face of the domain box; the face lies on a grid plane.
//  none      - open: the sparse grid simply grows (debris may fly anywhere)
//  fixed     - nodes on and beyond the plane have zero velocity
//  slip      - nodes on and beyond the plane have zero normal velocity
//  symmetry  - mirror plane: the grid field is made mirror-symmetric about the plane, so a half
//              model reproduces the full one (the paper halves its particle count this way)
//  outflow   - transmitting: material crossing the plane leaves the simulation, with its mass,
//              momentum and energy booked as outflow
enum class BoundaryKind : std::uint8_t { none, fixed, slip, symmetry, outflow };
constexpr std::string_view name_of(BoundaryKind b) {
  constexpr std::array<std::string_view, 5> kNames{"none", "fixed", "slip", "symmetry",
                                                   "outflow"};  // in the enum's order
  const auto i = static_cast<std::size_t>(b);
  return i < kNames.size() ? kNames[i] : "?";
}

// Faces in the order -x, +x, -y, +y, -z, +z.
struct Domain {
  Vec3 lo = Vec3::Constant(-std::numeric_limits<double>::infinity());
  Vec3 hi = Vec3::Constant(std::numeric_limits<double>::infinity());
  std::array<BoundaryKind, 6> faces{};  // all none
};

// MPI load balancing (docs/mpi.md, "Rebalancing"): every rebalance_every steps the migrate stage
// compares the largest particle count of a rank with the mean and recuts the Morton curve when
// the ratio exceeds `imbalance`. Results do not depend on them (any cut gives the same bits).
struct MpiTuning {
  unsigned rebalance_every = 10;
  double imbalance = 1.2;
};

// The MPM geometry (issue 31). three_d: the paper's 3-D engine. axisymmetric: the same engine in
// (r, z) = (x, z), torsion-free, every point at y = 0 standing for its full ring (mass and volume
// weighted by 2 pi r; Sulsky & Schreyer 1996, CMAME 139), the y stencil one node of weight 1,
// the hoop strain rate v_r / r in the velocity gradient and the hoop force in P2G, and the axis
// r = 0 a symmetry face (docs/validation-axisymmetric.md).
enum class Geometry : std::uint8_t { three_d, axisymmetric };

struct SolverConfig {
  Geometry geometry = Geometry::three_d;
  ShapeKind shape = ShapeKind::ugimp;
  TransferKind transfer = TransferKind::flip;
  // FLIP only: fraction of PIC velocity blended into the particle update, in [0, 1].
  double pic_fraction = 0.0;
  // XPIC only: the order m in [1, 32] (1 = PIC); 5 is the authors' suggested balance of
  // filtering and cost (m - 1 extra passes per step). Ignored by the other transfers.
  int xpic_order = 5;
  // FMPM only: the order k in [1, 32] (1 = PIC); k - 1 extra passes per step. Nairn (2026)
  // reports the disk impact's energy loss falling from 18.7% at k = 1 to below 2% for k > 6.
  int fmpm_order = 5;
  // XPIC and FMPM only: apply the filtered update on every N-th step (steps N, 2N, ... of the
  // run, counted by Clock::step, which checkpoints carry), FLIP on the others; 1 = every step.
  int filter_every = 1;
  // Filtering transfers (xpic, fmpm, FLIP with pic_fraction > 0) only: book the kinetic energy
  // the filtered particle update removes, against the plain FLIP update of the same step, as
  // internal energy of the points that carried it (DeBar 1974's kinetic-energy fix of
  // staggered-grid remaps; Benson 1992, CMAME 99). Off: the loss is booked nowhere.
  bool filter_heat = false;
  double cell_size = 0.0;  // h, edge of a grid cell (the paper's d_c)
  // Eq. 34 allows CFL 1; 0.3 leaves room for the sound speed growing within one step in shocks.
  double cfl = 0.3;
  // A step after which the stable step of Eq. 34 is shorter than the step taken by more than
  // this factor is taken again with the new, shorter step (see Simulation::step); 0 = never.
  // The step's effective CFL, cfl x taken / new stable step, is thereby kept below
  // retake_ratio x cfl (0.6 by default): at first contact of a 15 km/s impact the signal speed
  // (shocked sound speed + the viscosity's 2 (c_L c + c_Q h |div v|)) jumps ~4x within one step,
  // which a CFL of 0.3 alone does not cover (docs/stability.md, observation 2).
  double retake_ratio = 2.0;
  double dt_max = std::numeric_limits<double>::infinity();
  // A time step below dt_min stops the run with an error (time-step collapse), rather than
  // crawling forever; 0 disables the check.
  double dt_min = 0.0;
  Vec3 gravity = Vec3::Zero();
  gravity::GravityConfig self_gravity;  // [gravity]: self-gravity and the equilibrium start
  // Optional body force per unit mass at each particle (Eq. 30, b_p), e.g. the source term of a
  // manufactured solution. Called once per step at t^n with the particles and three arrays to
  // fill; leave empty when unused (it then costs nothing).
  std::function<void(double t, const ParticleStore&, double* bx, double* by, double* bz)>
      body_force;
  Domain domain;
  ArtificialViscosity viscosity;
  // single_field keeps every earlier result bitwise (and is the paper's choice).
  ContactConfig contact;
  // Physically re-order particle columns by grid block every this many steps (between re-orders
  // the block lists are index lists into the columns). 0 = never.
  unsigned reorder_interval = 25;
  MpiTuning mpi;  // several MPI ranks only
};

}  // namespace shatter
