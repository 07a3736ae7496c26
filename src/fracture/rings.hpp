#pragma once
// r-z rings in the fragment search (issue 31): a point of an axisymmetric run stands for the ring
// it sweeps about z, volume V = 2 pi r A (Sulsky & Schreyer 1996); the half-plane search works on
// the cross-sections A.

#include <vector>

#include "shatter/core/particles.hpp"

namespace shatter::fracture {

// Current cross-section of each ring, storage order: A = V / (2 pi r), V = m / rho where the store
// has rho (> 0), else volume0; r = x. A ring of radius r <= 0 (on the axis) has no cross-section
// to speak of and gets A = 0.
std::vector<double> ring_areas(const ParticleStore& store);

}  // namespace shatter::fracture
