// Simulation: the MPM solver's set-up (the columns the stages need, the ranks) and its
// accessors. The transfer scheme is decided once, in mpm::TransferPolicy. The step is
// src/mpm/step.cpp, its stages src/mpm/stages/.

#include "shatter/mpm/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numeric>
#include <utility>

#include <fmt/format.h>

#include "mpm/axisymmetric.hpp"
#include "mpm/loops.hpp"
#include "mpm/stages/stages.hpp"
#include "mpm/state.hpp"
#include "parallel/exact_reduce.hpp"
#include "parallel/mpm/exchanges.hpp"
#include "shatter/core/solver_inputs.hpp"

namespace shatter {
namespace mpm {
void build_stages(State& s);     // step.cpp
void refresh_timings(State& s);  // step.cpp
}  // namespace mpm

namespace {

const FieldSet kEngineFields =
    kPosition | kVelocity | kStress | FieldSet{Field::mass,      Field::volume0, Field::size0,
                                               Field::rho,       Field::energy,  Field::pressure,
                                               Field::soundspeed};

void check_config(const SolverConfig& c) {
  if (!(c.cell_size > 0.0) || !std::isfinite(c.cell_size)) {
    throw std::invalid_argument(fmt::format("solver: cell_size must be > 0, got {}", c.cell_size));
  }
  if (!(c.cfl > 0.0 && c.cfl <= 1.0)) {
    throw std::invalid_argument(
        fmt::format("solver: cfl must be in (0, 1] (Eq. 34), got {}", c.cfl));
  }
}

// The columns the stages and the models need, and the particle sizes uGIMP needs.
void prepare_store(ParticleStore& P, const std::vector<MaterialPtr>& materials,
                   const mpm::TransferPolicy& transfer) {
  if (P.has(Field::size0)) {
    // A zero size would make the uGIMP weights 0/0; such particles get the cubic-lattice size.
    auto s = P.col(Field::size0);
    for (std::size_t p = 0; p < P.size(); ++p) {
      if (!(s[p] > 0.0)) s[p] = std::cbrt(P.col(Field::mass)[p] / P.col(Field::rho)[p]);
    }
  }
  if (!P.has(Field::size0)) {
    // uGIMP needs the undeformed particle size; without one, take the spacing of a cubic lattice
    // of the particle's volume.
    P.require(Field::size0);
    auto s = P.col(Field::size0);
    auto m = P.col(Field::mass);
    auto r = P.col(Field::rho);
    for (std::size_t p = 0; p < P.size(); ++p) s[p] = std::cbrt(m[p] / r[p]);
  }
  P.require(kEngineFields);
  // C_p starts at zero: the scene gives velocities, not their gradients.
  if (transfer.affine) P.require(kVelocityGradient);
  P.require(IField::id);
  for (const auto& m : materials) P.require(m->fields());
  for (const Group& g : P.groups()) {
    materials[static_cast<std::size_t>(g.material)]->initialise(P, g.range);
  }
}

// Multi-velocity-field contact, when the scene asks for it and has two bodies or more.
std::unique_ptr<mpm::Contact> make_contact(const ContactConfig& cc, const ParticleStore& P) {
  if (!(cc.friction >= 0.0 && std::isfinite(cc.friction))) {
    throw std::invalid_argument(
        fmt::format("solver: contact friction must be finite and >= 0, got {}", cc.friction));
  }
  for (const ContactPair& pr : cc.pairs) {
    constexpr std::int64_t kMaxId = std::int64_t{1} << 32;  // mpm::Contact's pair key
    if (!(pr.friction >= 0.0 && std::isfinite(pr.friction)) || pr.a < 0 || pr.b < 0 ||
        pr.a >= kMaxId || pr.b >= kMaxId || pr.a == pr.b) {
      throw std::invalid_argument(fmt::format(
          "solver: contact pair ({}, {}) needs two different body ids in [0, 2^32) and a "
          "finite friction >= 0, got {}",
          pr.a, pr.b, pr.friction));
    }
  }
  if (cc.kind != ContactKind::multi_field || !P.has(IField::body)) return nullptr;
  const auto body = P.col(IField::body);
  const auto [lo, hi] = std::minmax_element(body.begin(), body.end());
  if (*lo < 0) {
    throw std::invalid_argument(fmt::format(
        "particle {} has body id {} (multi-field contact needs ids >= 0)", lo - body.begin(), *lo));
  }
  return *lo != *hi ? std::make_unique<mpm::Contact>(cc) : nullptr;
}

// Several ranks (docs/mpi.md): what the decomposition does not carry yet is refused, on every
// rank alike, rather than run with results that depend on the rank count.
void setup_ranks(mpm::State& s) {
  if (s.contact) {
    throw std::invalid_argument(
        "solver: contact 'multi_field' is not supported on more than one MPI rank yet (body "
        "copies would need the meetings of every rank); run it on one rank");
  }
  // Symmetry and fixed faces: ghost nodes and their partners get one owner, who mirrors them
  // (the halo exchange).
  std::vector<std::pair<int, std::int64_t>> planes;
  for (const auto& pl : s.boundaries.planes()) {
    if (pl.kind == BoundaryKind::symmetry || pl.kind == BoundaryKind::fixed) {
      planes.emplace_back(pl.axis, pl.index);
    }
  }
  s.ranks.decomp.set_planes(std::move(planes));
  // Checked by the scene ([solver.mpi]); a caller's 0 still checks every step.
  s.ranks.rebalance_every = std::max(1U, s.config.mpi.rebalance_every);
  s.ranks.imbalance = s.config.mpi.imbalance;
}

// One exact sum over the ranks.
double global(const mpm::State& s, parallel::ExactSum sum) {
  if (s.dist()) {
    parallel::ExactSum* one[1] = {&sum};
    parallel::sum_over_ranks(s.ranks.comm, one);
  }
  return sum.value();
}

// The accounts at t = 0: v^0 is both the "synchronised" and the stored velocity.
void initial_energy(const mpm::State& s, EnergyBudget& E) {
  const ParticleStore& P = s.particles;
  const auto m = P.col(Field::mass), e = P.col(Field::energy);
  const auto vx = P.col(Field::vx), vy = P.col(Field::vy), vz = P.col(Field::vz);
  const auto x = P.col(Field::x), y = P.col(Field::y), z = P.col(Field::z);
  const Vec3 g = s.config.gravity;
  E.kinetic = global(s, mpm::exact_sum(P.size(), [&](std::size_t p) {
                       return 0.5 * m[p] * (vx[p] * vx[p] + vy[p] * vy[p] + vz[p] * vz[p]);
                     }));
  E.internal = global(s, mpm::exact_sum(P.size(), [&](std::size_t p) { return m[p] * e[p]; }));
  E.potential = global(s, mpm::exact_sum(P.size(), [&](std::size_t p) {
                         return -m[p] * (g.x() * x[p] + g.y() * y[p] + g.z() * z[p]);
                       }));
  E.initial = E.total();
  E.scale = std::abs(E.kinetic) + std::abs(E.internal);
}

}  // namespace

Simulation::Simulation(SolverConfig config, ParticleStore particles,
                       std::vector<MaterialPtr> materials, int threads)
    : config_(std::move(config)),
      particles_(std::move(particles)),
      materials_(std::move(materials)),
      threads_(threads) {
  check_config(config_);
  check_solver_inputs(
      particles_, materials_,
      {Field::x, Field::y, Field::z, Field::vx, Field::vy, Field::vz, Field::mass, Field::rho});
  // The transfer scheme, decided once (mpm::TransferPolicy).
  const mpm::TransferPolicy transfer = mpm::TransferPolicy::from(config_);
  prepare_store(particles_, materials_, transfer);
  state_ = std::make_unique<mpm::State>(config_, particles_, materials_, clock_, energy_, transfer,
                                        threads);
  mpm::State& s = *state_;
  mpm::check_axisymmetric(config_, particles_, s.dist());
  s.contact = make_contact(config_.contact, particles_);
  const auto masses = particles_.col(Field::mass);
  s.empty_mass = 1e-12 * *std::min_element(masses.begin(), masses.end());
  if (s.dist()) setup_ranks(s);
  s.arena.execute([&] {
    mpm::build_stages(s);
    mpm::check_finite(s);
    if (s.dist()) {
      // Every rank built the whole scene (the same bits: flaws are drawn per particle id);
      // each keeps the particles of its piece of the curve.
      mpm::with_shape(config_.shape, [&]<class Shape>() { parallel::distribute<Shape>(s); });
    }
    initial_energy(s, energy_);
    s.internal_next = energy_.internal;
    const double fast = mpm::fastest_local(s);
    clock_.dt = mpm::stable_dt(s, s.dist() ? s.ranks.comm.max(fast) : fast);
  });
  mpm::refresh_timings(s);
}

Simulation::~Simulation() = default;

std::size_t Simulation::active_blocks() const {
  return state_->grid.blocks();
}
std::size_t Simulation::grid_bytes() const {
  return state_->grid.bytes();
}
double Simulation::grid_mass() const {
  const auto& m = state_->grid.nodes().mass;
  return std::accumulate(m.begin(), m.end(), 0.0);
}
const std::vector<StageTiming>& Simulation::stage_timings() const {
  return state_->timings;
}
std::vector<std::string> Simulation::stage_names() const {
  std::vector<std::string> out;
  for (const StageTiming& t : state_->graph.timings()) out.push_back(t.name);
  return out;
}
parallel::Traffic Simulation::halo_traffic() const {
  return state_->ranks.halo_traffic;
}
parallel::Traffic Simulation::migrate_traffic() const {
  return state_->ranks.migrate_traffic;
}
std::uint64_t Simulation::rebalances() const {
  return state_->ranks.rebalances;
}

void Simulation::set_driven(const std::vector<std::int32_t>& bodies) {
  if (bodies.empty()) {
    state_->driven.reset();
    return;
  }
  if (state_->dist()) {
    throw std::invalid_argument(
        "driven bodies (body.NAME.driven) run on one MPI rank only: the prescribed nodes of a "
        "body that several ranks share are not exchanged");
  }
  state_->driven = std::make_unique<mpm::DrivenBodies>(particles_, bodies);
}

void Simulation::restore(const Clock& clock, const EnergyBudget& energy) {
  clock_ = clock;
  energy_ = energy;
  state_->internal_next = global(*state_, mpm::exact_sum(particles_.size(), [&](std::size_t p) {
    return particles_.col(Field::mass)[p] * particles_.col(Field::energy)[p];
  }));
}

void Simulation::restore(const Clock& clock, const EnergyBudget& energy, double internal_next) {
  clock_ = clock;
  energy_ = energy;
  state_->internal_next = internal_next;
}

double Simulation::internal_next() const {
  return state_->internal_next;
}

}  // namespace shatter
