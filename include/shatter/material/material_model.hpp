#pragma once
// The constitutive seam (ISSUE: engine item 8; DESIGN.md "Physics modules"). The engine's
// constitutive stage calls one MaterialModel per material group, once per step, over the group's
// contiguous particle range. A model is chosen per group at set-up (one virtual call per group,
// never per particle); inside, it runs a kernel compiled for its (EOS, strength, damage)
// combination.

#include <memory>
#include <string>

#include "shatter/core/particles.hpp"

namespace shatter {

// Bulk artificial viscosity (von Neumann–Richtmyer quadratic + linear), applied on compression.
struct ArtificialViscosity {
  double linear = 0.0;     // c_L, multiplies rho * c * h * |div v|
  double quadratic = 0.0;  // c_Q, multiplies rho * (h * div v)^2
};

// What a model's update needs from the engine besides the columns.
struct ConstitutiveContext {
  double dt = 0.0;         // the step over which deps and dspin were accumulated
  double cell_size = 0.0;  // background-grid cell size h (artificial viscosity length)
  ArtificialViscosity viscosity;
  // r-z (issue 31): each point is a ring about z at radius x; the damage's crack-growth length
  // R_s is then that of the ring's cross-section (kernels/constitutive/composed_kernel.hpp).
  bool rings = false;
};

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
  // the engine from tr(deps)), deps_* and dspin_* hold the increments over ctx.dt, and stress,
  // energy and model state hold their values at step n. On exit: stress (the Cauchy stress the
  // momentum equation sees, damage included), pressure, energy and soundspeed (the longitudinal
  // speed c_p used for the time step, Eq. 34) hold step n+1 values.
  virtual void update(ParticleStore& store, Range range, const ConstitutiveContext& ctx) const = 0;
};

using MaterialPtr = std::shared_ptr<const MaterialModel>;

}  // namespace shatter
