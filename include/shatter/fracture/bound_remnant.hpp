#pragma once
// The largest gravitationally bound aggregate of a fragment catalogue, by the iterative energy
// criterion of Benz & Asphaug 1999 (Icarus 142, Sec. 3.3): seed with the largest fragment; add
// every fragment whose kinetic energy relative to the aggregate's centre of mass is below its
// gravitational binding energy to the aggregate, 1/2 m |v - V|^2 < G M m / |r - R|; recompute
// the aggregate; repeat until nothing joins (a fixed point: membership only grows, so at most
// one pass per fragment). Fragments are point masses at their centres of mass; dust (mass in no
// fragment) is left out, which can only make the remnant smaller. Implemented in
// src/fracture/bound_remnant.cpp.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "shatter/fracture/fragments.hpp"

namespace shatter {

struct BoundRemnant {
  double mass = 0.0;  // kg; 0 when the catalogue has no fragment
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  // About the aggregate's centre of mass: the fragments' own spins plus their orbital motion.
  Eigen::Vector3d angular_momentum = Eigen::Vector3d::Zero();
  Eigen::Vector3d omega = Eigen::Vector3d::Zero();  // I^-1 L, rad/s
  std::vector<std::int64_t> members;                // fragment ids, largest first
  int iterations = 0;                               // passes until the fixed point
  // bound_remnant_with_dust only: the dust points in the remnant, their mass, and which start
  // gave the larger aggregate ("largest fragment" or "self-bound bulk").
  bool with_dust = false;
  double dust_mass = 0.0;  // kg
  std::int64_t dust_points = 0;
  std::string seed = "largest fragment";
  double speed() const { return velocity.norm(); }
  double spin() const { return omega.norm(); }
};

// G: the constant of gravitation (gravity::kNewtonG in SI; other values for tests in G = 1 units).
BoundRemnant bound_remnant(const FragmentCatalogue& cat, double G);

// The same criterion with every dust point (IField::fragment < 0 in `store`, the store the
// catalogue was found from) as a body of its own beside the fragments, as BA99 do with their
// SPH particles: in the gravity regime the target is shattered to dust and its bulk is still
// bound. Two starts, the larger bound aggregate wins: BA99's growth from the largest fragment,
// and the bulk bound to itself (every body, dropping those not bound to the aggregate of the
// rest until none is dropped, then grown again). Throws std::invalid_argument when the store
// has no fragment labels.
BoundRemnant bound_remnant_with_dust(const FragmentCatalogue& cat, const ParticleStore& store,
                                     double G);

// PREFIX_bound.json beside the fragment table: mass (kg and fraction of the total), centre,
// velocity and speed, spin vector and rate, member fragment ids, passes.
void write_bound_remnant_json(const BoundRemnant& r, const FragmentCatalogue& cat,
                              const std::filesystem::path& file);

}  // namespace shatter
