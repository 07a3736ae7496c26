#pragma once
// Restores the full body from a half model (symmetry plane through the origin), for
// post-processing that needs whole fragments: fragment masses, shapes and spins.

#include "shatter/core/particles.hpp"

namespace shatter::io {

// Every group g of the result holds group g's particles followed by their mirror images across
// the plane x_axis = 0: that coordinate, and every vector and tensor component with exactly one
// index along the axis, change sign. Mirror images get new ids (max id + 1 + original id).
ParticleStore mirrored(const ParticleStore& half, int axis);

}  // namespace shatter::io
