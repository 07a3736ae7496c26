#pragma once
// The pieces of scene parsing, one per section of the file.

#include <optional>
#include <string>

#include <toml++/toml.h>

#include "scene/reader.hpp"
#include "shatter/material/catalogue.hpp"
#include "shatter/scene/scene.hpp"

namespace shatter::scene {

// The table `key` of `parent`, inserted empty when the scene has none (so that the defaults read
// from it are written into the resolved scene).
toml::table& table_or_empty(Reader& parent, const char* key);

// [solver] and [domain]; fills scene.solver, end_time, symmetry_axis.
void read_solver(Reader& root, Scene& scene);
void read_domain(Reader& root, Scene& scene);
// solver.contact_pair names bodies: resolved to body ids once the bodies are read.
void resolve_contact_pairs(Scene& scene);

// [gravity] (parse_gravity.cpp), after [solver] and [domain]; fills scene.solver.self_gravity.
void read_gravity(Reader& root, Scene& scene);

// [beta] (parse_beta.cpp), after the bodies and [impact]; fills scene.beta.
void read_beta(Reader& root, Scene& scene);

// [fracture] and [output].
void read_fracture(Reader& root, Scene& scene);
void read_output(Reader& root, Scene& scene);

// The impact helper's inputs, read before the bodies (it places the projectile).
struct ImpactInput {
  std::string projectile, target;
  double speed = 0.0, angle_deg = 0.0, gap = 0.0;
  Vec3 direction = Vec3::UnitX(), offset = Vec3::UnitY();
  std::string where_projectile, where_target, where_direction, where_offset;
};
std::optional<ImpactInput> read_impact(Reader& root, const Scene& scene);

// One [body.NAME] table. `placed_by_impact` says the [impact] helper sets its centre and velocity.
BodySpec read_body(Reader& body, const std::string& name, const Scene& scene,
                   const MaterialCatalogue& catalogue, bool placed_by_impact);

// A body's `material` (a catalogue name, or a table of a name and overrides) and its [damage]
// (parse_body.cpp); also read for a boulder field.
MaterialSpec read_material(Reader& body, const MaterialCatalogue& catalogue);
void read_damage(Reader& r, BodySpec& b, const Scene& scene);

// [body.NAME.boulders] (parse_boulders.cpp): places the host's random boulder field, cuts it out
// of the host's shape and returns the boulder body (NAME_boulders); none without the table.
std::optional<BodySpec> read_boulders(Reader& body, BodySpec& host, Scene& scene,
                                      const MaterialCatalogue& catalogue);

// Places the projectile against the target (MPM paper Fig. 4) and fills it with points.
void apply_impact(const ImpactInput& in, Scene& scene);

// Refuses a lattice rotation that a symmetry plane does not allow (a turn not about its normal).
void check_lattice_rotation(const Scene& scene, const BodySpec& b);

// solver.geometry = "axisymmetric" (src/scene/axisymmetric_check.cpp): refuses a body that is
// not a body of revolution about the z axis or that moves off it, naming the key.
void check_axisymmetric_body(const BodySpec& b);

// Fills every body with points and checks them against each other and the domain.
void fill_and_check_bodies(Scene& scene);

}  // namespace shatter::scene
