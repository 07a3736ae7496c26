// Setting up the SPH solver: the checks of its configuration and of the store it is given, the
// working state, and the first forces and time step.

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "shatter/core/solver_inputs.hpp"
#include "sph/solver_impl.hpp"

namespace shatter::sph {
namespace {

const FieldSet kSphFields =
    kPosition | kVelocity | kStress | kStrainIncrement | kSpinIncrement |
    FieldSet{Field::mass, Field::rho, Field::energy, Field::pressure, Field::soundspeed};

constexpr const char* kFaces[6] = {"x_lo", "x_hi", "y_lo", "y_hi", "z_lo", "z_hi"};

double face_bound(const SolverConfig& config, std::size_t f) {
  const int a = static_cast<int>(f / 2);
  return f % 2 == 0 ? config.domain.lo[a] : config.domain.hi[a];
}

// The numbers of [solver] and [solver.sph] this solver reads.
void check_settings(const SolverConfig& config, const SphConfig& sph) {
  if (!(config.cfl > 0.0 && config.cfl <= 1.0)) {
    throw std::invalid_argument(fmt::format("solver: cfl must be in (0, 1], got {}", config.cfl));
  }
  if (!(sph.h_factor > 0.0) || !std::isfinite(sph.h_factor)) {
    throw std::invalid_argument(
        fmt::format("solver.sph: h_factor must be > 0, got {}", sph.h_factor));
  }
  if (!(sph.skin >= 0.0) || !std::isfinite(sph.skin)) {
    throw std::invalid_argument(fmt::format("solver.sph: skin must be >= 0, got {}", sph.skin));
  }
  if (sph.viscosity_switch == ViscositySwitch::morris_monaghan &&
      !(sph.alpha_min >= 0.0 && sph.alpha_min <= sph.alpha_max && std::isfinite(sph.alpha_max) &&
        sph.switch_decay > 0.0 && std::isfinite(sph.switch_decay))) {
    throw std::invalid_argument(fmt::format(
        "solver.sph: the viscosity switch needs 0 <= alpha_min <= alpha_max and switch_decay > 0, "
        "got alpha_min = {}, alpha_max = {}, switch_decay = {}",
        sph.alpha_min, sph.alpha_max, sph.switch_decay));
  }
  if (!(sph.alpha >= 0.0) || !(sph.beta >= 0.0)) {
    throw std::invalid_argument(
        fmt::format("solver.sph: alpha and beta must be >= 0, got {} and {}", sph.alpha, sph.beta));
  }
}

// The domain faces SPH has (none, symmetry, slip, outflow), each at a finite place; no body
// force.
void check_faces(const SolverConfig& config) {
  for (std::size_t f = 0; f < 6; ++f) {
    const BoundaryKind k = config.domain.faces[f];
    if (k == BoundaryKind::fixed) {
      throw std::invalid_argument(fmt::format(
          "solver.method = \"sph\": domain face {} is 'fixed' (no-slip walls are not implemented "
          "for SPH; 'slip', 'symmetry', 'outflow' and 'none' are)",
          kFaces[f]));
    }
    const double bound = face_bound(config, f);
    if (k != BoundaryKind::none && !std::isfinite(bound)) {
      throw std::invalid_argument(
          fmt::format("solver.method = \"sph\": domain face {} is '{}' but lies at {}", kFaces[f],
                      name_of(k), bound));
    }
  }
  if (config.body_force) {
    throw std::invalid_argument("solver.method = \"sph\" does not take a body force yet");
  }
}

// A particle behind a reflecting face would overlap its own image.
void check_in_front_of_mirrors(const SolverConfig& config, const ParticleStore& particles) {
  for (std::size_t f = 0; f < 6; ++f) {
    const BoundaryKind k = config.domain.faces[f];
    if (k != BoundaryKind::symmetry && k != BoundaryKind::slip) continue;
    const int a = static_cast<int>(f / 2);
    const double bound = face_bound(config, f);
    const auto x = particles.col(a == 0 ? Field::x : a == 1 ? Field::y : Field::z);
    for (std::size_t p = 0; p < particles.size(); ++p) {
      if (f % 2 == 0 ? x[p] < bound : x[p] > bound) {
        throw std::invalid_argument(fmt::format(
            "solver.method = \"sph\": particle {} ({} = {}) lies beyond the {} face {} at {}", p,
            "xyz"[a], x[p], name_of(k), kFaces[f], bound));
      }
    }
  }
}

}  // namespace

SphSolver::Impl::Impl(SphSolver& solver, int threads)
    : s(solver), arena(threads > 0 ? threads : tbb::task_arena::automatic) {
  for (const char* name : {"kick", "rates", "material", "drift", "search", "forces", "energy"}) {
    timings.push_back({name, 0.0});
  }
  for (std::size_t f = 0; f < 6; ++f) {
    const BoundaryKind k = s.config_.domain.faces[f];
    mirror_face[f] = k == BoundaryKind::symmetry || k == BoundaryKind::slip;
    outflow_face[f] = k == BoundaryKind::outflow;
    mirrors = mirrors || mirror_face[f];
    outflows = outflows || outflow_face[f];
  }
  start_switch();
}

SphSolver::SphSolver(SolverConfig config, SphConfig sph, ParticleStore particles,
                     std::vector<MaterialPtr> materials, int threads)
    : config_(std::move(config)),
      sph_(sph),
      particles_(std::move(particles)),
      materials_(std::move(materials)),
      threads_(threads) {
  check_settings(config_, sph_);
  check_faces(config_);
  check_solver_inputs(
      particles_, materials_,
      {Field::x, Field::y, Field::z, Field::vx, Field::vy, Field::vz, Field::mass, Field::rho});
  check_in_front_of_mirrors(config_, particles_);
  particles_.require(kSphFields);
  particles_.require(IField::id);
  for (const auto& m : materials_) particles_.require(m->fields());
  for (const Group& g : particles_.groups()) {
    materials_[static_cast<std::size_t>(g.material)]->initialise(particles_, g.range);
  }

  impl_ = std::make_unique<Impl>(*this, threads);
  impl_->arena.execute([&] {
    impl_->search_and_forces(true);
    impl_->energy();
    energy_.initial = energy_.total();
    energy_.scale = std::abs(energy_.kinetic) + std::abs(energy_.internal);
    impl_->next_dt();
  });
}

}  // namespace shatter::sph
