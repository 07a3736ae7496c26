#pragma once
// The scene's [gravity] table (src/scene/parse_gravity.cpp): self-gravity of the bodies' own
// mass and the lithostatic start. The uniform field stays solver.gravity.

#include "shatter/gravity/mesh_gravity.hpp"

namespace shatter::gravity {

struct GravityConfig {
  bool self = false;  // the particles attract each other (MeshGravity)
  int mesh = 64;      // mesh nodes per side over the mass's bounding box (MeshGravity)
  double G = kNewtonG;
  // dt <= dt_factor sqrt(cell / max |a|) (gravity_time_step); the sound-speed step is far
  // shorter for rock bodies, so this binds only for fluids, dust or free fall.
  double dt_factor = 0.5;
  // Start each body in hydrostatic equilibrium under its own gravity (equilibrium.hpp).
  bool equilibrium = false;
};

}  // namespace shatter::gravity
