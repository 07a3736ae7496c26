#include "shatter/scene/build.hpp"

#include <algorithm>

#include "shatter/fracture/flaws.hpp"
#include "shatter/gravity/equilibrium.hpp"

namespace shatter::scene {

std::vector<MaterialPtr> build_materials(const Scene& scene) {
  std::vector<MaterialPtr> materials;
  for (const BodySpec& b : scene.bodies) materials.push_back(make_material(b.material, b.damage));
  return materials;
}

std::vector<bool> damaged_groups(const Scene& scene) {
  std::vector<bool> d;
  for (const BodySpec& b : scene.bodies) d.push_back(b.damage.model != "none");
  return d;
}

namespace {

// How many copies of a body's points make the body whose flaws are drawn (MPM paper Sec. 3.3:
// V and n_p are the body's). A body cut by the symmetry plane is one body of which the half
// model holds half: its lattice then has a layer at half a spacing from the plane, and the
// mirror image of that layer is its neighbour across the plane, so the image joins it: 2. A body
// clear of the plane is one of two separate bodies, each with its own flaws: 1.
std::size_t flaw_copies(const Scene& scene, const BodySpec& b) {
  const int a = scene.symmetry_axis;
  if (a < 0) return 1;
  for (const Vec3& x : b.fill.points) {
    if (x[a] < b.spacing) return 2;
  }
  return 1;
}

}  // namespace

BuiltScene build(const Scene& scene) {
  BuiltScene s;
  s.materials = build_materials(scene);
  s.damaged = damaged_groups(scene);

  ParticleStore& P = s.particles;
  P.require(FieldSet{Field::x, Field::y, Field::z, Field::vx, Field::vy, Field::vz, Field::mass,
                     Field::volume0, Field::size0, Field::rho, Field::energy});
  P.require(IField::id);
  P.require(IField::body);
  for (const auto& m : s.materials) P.require(m->fields());
  if (std::any_of(s.damaged.begin(), s.damaged.end(), [](bool d) { return d; })) {
    P.require(Field::damage);
  }

  std::int64_t next_id = 0;
  for (std::size_t g = 0; g < scene.bodies.size(); ++g) {
    const BodySpec& b = scene.bodies[g];
    const auto& pts = b.fill.points;
    const Range r = P.add_group(static_cast<int>(g), pts.size());
    const double rho0 = s.materials[g]->reference_density();
    // Volume-weighted so the body has its true mass (and momentum) whatever the resolution.
    const double v0 = b.fill.volume / static_cast<double>(pts.size());
    for (std::size_t k = 0; k < pts.size(); ++k) {
      const std::size_t p = r.begin + k;
      P.col(Field::x)[p] = pts[k].x();
      P.col(Field::y)[p] = pts[k].y();
      P.col(Field::z)[p] = pts[k].z();
      P.col(Field::vx)[p] = b.velocity.x();
      P.col(Field::vy)[p] = b.velocity.y();
      P.col(Field::vz)[p] = b.velocity.z();
      P.col(Field::rho)[p] = rho0;
      // r-z: each point is a ring, of its own volume (fill_lattice_rz)
      const double v = b.fill.volumes.empty() ? v0 : b.fill.volumes[k];
      P.col(Field::volume0)[p] = v;
      P.col(Field::mass)[p] = rho0 * v;
      P.col(Field::size0)[p] = b.spacing;
      P.col(Field::energy)[p] = b.energy;
      P.col(IField::id)[p] = next_id++;
      P.col(IField::body)[p] = static_cast<std::int64_t>(g);
    }
    if (b.flaws) {
      FlawSpec flaws = *b.flaws;  // r-z: a ring holds the flaws of one 3-D point of its size
      flaws.rings = scene.solver.geometry == Geometry::axisymmetric;
      initialise_flaws(P, r, flaws, flaw_copies(scene, b));
    }
  }
  const gravity::GravityConfig& g = scene.solver.self_gravity;
  // The lithostatic start: under self-gravity, or else under the uniform field along -z with a
  // floor (parse_gravity.cpp refuses any other set-up). Porous bodies start on their crush curve
  // (issue 29): their materials' compaction at rest.
  if (g.equilibrium) {
    std::vector<RestCompactionFn> rest;
    for (const BodySpec& b : scene.bodies) {
      rest.push_back(b.material.porosity.empty() ? RestCompactionFn{}
                                                 : rest_compaction(b.material));
    }
    if (g.self) {
      gravity::set_equilibrium(P, s.materials, g.G, rest);
    } else {
      gravity::set_uniform_equilibrium(P, s.materials, -scene.solver.gravity.z(),
                                       scene.solver.domain.lo.z(), scene.solver.cell_size, rest);
    }
  }
  return s;
}

}  // namespace shatter::scene
