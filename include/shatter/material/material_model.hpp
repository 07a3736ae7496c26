#pragma once
// The constitutive seam (ISSUE: engine item 8; DESIGN.md "Physics modules"). The engine's
// constitutive stage calls one MaterialModel per material group, once per step, over the group's
// contiguous particle range. A model is chosen per group at set-up (one virtual call per group,
// never per particle); inside, it runs a kernel compiled for its (EOS, strength, damage)
// combination.

#include <cstddef>
#include <memory>
#include <string>

#include "shatter/core/particles.hpp"

namespace shatter {

// Bulk artificial viscosity (von Neumann–Richtmyer quadratic + linear), applied on compression.
struct ArtificialViscosity {
  double linear = 0.0;     // c_L, multiplies rho * c * h * |div v|
  double quadratic = 0.0;  // c_Q, multiplies rho * (h * div v)^2
};

// The strain and spin increments of the particles being updated, in buffers the caller owns
// (issue 35: the MPM step computes them per chunk of particles, right before the update, and
// keeps no store column of them): particle p's deps_k at deps[k][p - begin] (xx, yy, zz, xy,
// yz, xz, tensor components), its dspin_k at dspin[k][p - begin] (xy, yz, xz).
struct IncrementViews {
  const double* deps[6] = {};
  const double* dspin[3] = {};
  std::size_t begin = 0;  // the store index of the buffers' first entry
};

// What a model's update needs from the engine besides the columns.
struct ConstitutiveContext {
  double dt = 0.0;         // the step over which deps and dspin were accumulated
  double cell_size = 0.0;  // background-grid cell size h (artificial viscosity length)
  ArtificialViscosity viscosity;
  // r-z (issue 31): each point is a ring about z at radius x; the damage's crack-growth length
  // R_s is then that of the ring's cross-section (kernels/constitutive/composed_kernel.hpp).
  bool rings = false;
  // The increments; null: the store's deps_* and dspin_* columns (SPH, tests, benchmarks).
  const IncrementViews* increments = nullptr;
};

// The increments a model's update reads: the context's views, else the store's columns.
inline IncrementViews increments_of(ParticleStore& store, const ConstitutiveContext& ctx) {
  if (ctx.increments != nullptr) return *ctx.increments;
  constexpr Field deps[6] = {Field::deps_xx, Field::deps_yy, Field::deps_zz,
                             Field::deps_xy, Field::deps_yz, Field::deps_xz};
  constexpr Field spin[3] = {Field::dspin_xy, Field::dspin_yz, Field::dspin_xz};
  IncrementViews v;
  for (int k = 0; k < 6; ++k) v.deps[k] = store.col(deps[k]).data();
  for (int k = 0; k < 3; ++k) v.dspin[k] = store.col(spin[k]).data();
  return v;
}

class MaterialModel {
 public:
  virtual ~MaterialModel() = default;

  // Name as in the catalogue / scene (for messages and output).
  virtual std::string name() const = 0;

  // Columns this model needs besides the engine's own (e.g. plastic_strain, damage, sdev_*).
  // The scene registers them before particles are created.
  virtual FieldSet fields() const { return {}; }

  // Reference (intact, zero-pressure) density.
  virtual double reference_density() const = 0;

  // Sets consistent initial state for freshly created particles of this group: pressure and
  // sound speed from (rho, energy), any model state. Called once after set-up.
  virtual void initialise(ParticleStore& store, Range range) const = 0;

  // App. A.2 step 7 for particles in `range`. On entry: rho holds rho^{n+1} (already updated by
  // the engine from tr(deps)), increments_of(store, ctx) holds the increments over ctx.dt, and
  // stress, energy and model state hold their values at step n. On exit: stress (the Cauchy stress
  // the momentum equation sees, damage included), pressure, energy and soundspeed (the longitudinal
  // speed c_p used for the time step, Eq. 34) hold step n+1 values. The MPM step calls it per
  // chunk of a group (src/mpm/stages/constitutive.cpp), concurrently on disjoint ranges: a
  // model's update writes only the rows of its range.
  virtual void update(ParticleStore& store, Range range, const ConstitutiveContext& ctx) const = 0;
};

using MaterialPtr = std::shared_ptr<const MaterialModel>;

}  // namespace shatter
