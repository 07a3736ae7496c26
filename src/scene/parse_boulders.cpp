// [body.NAME.boulders]: a random boulder field inside a body (issue 32;
// include/shatter/scene/boulders.hpp says how it is drawn; docs/scenes.md, "Boulders").

#include <fmt/format.h>

#include "scene/parts.hpp"
#include "shatter/scene/boulders.hpp"

namespace shatter::scene {

namespace {

// The field's keys (volume fraction, sizes, seed, region), checked; the placement's inputs.
BoulderParams read_params(Reader& r, const BodySpec& host, const Scene& scene) {
  BoulderParams p;
  p.volume_fraction = r.number("volume_fraction");
  r.note_range("volume_fraction", "(0, 0.6]; of the host's volume (inside the region)");
  if (!(p.volume_fraction > 0.0 && p.volume_fraction <= 0.6)) {
    r.fail("volume_fraction", fmt::format("must be in (0, 0.6] (got {}): random placement of "
                                          "spheres jams near 0.4",
                                          p.volume_fraction));
  }
  p.radius_min = r.positive("radius_min", r.number("radius_min"));
  p.radius_max = r.positive("radius_max", r.number("radius_max"));
  r.note_range("radius_min", ">= the host's point spacing; <= radius_max", "m");
  r.note_range("radius_max", ">= radius_min; fits in the host", "m");
  if (p.radius_min > p.radius_max) {
    r.fail("radius_min",
           fmt::format("= {} m exceeds radius_max = {} m", p.radius_min, p.radius_max));
  }
  if (p.radius_min < host.spacing) {
    r.fail("radius_min",
           fmt::format("= {} m is below the host's point spacing {} m: a smaller boulder may "
                       "hold no point (coarser boulders or a finer spacing)",
                       p.radius_min, host.spacing));
  }
  p.exponent = r.positive("exponent", r.number("exponent"));
  r.note_range("exponent", "q of the cumulative size-frequency distribution N(>r) ~ r^-q");
  const auto seed = r.integer("seed", static_cast<std::int64_t>(scene.fracture.seed));
  r.note_default("seed", "fracture.seed");
  r.note_range("seed", ">= 0");
  if (seed < 0) r.fail("seed", "must be >= 0");
  p.seed = static_cast<std::uint64_t>(seed);
  const auto lo = r.optional_vec3("region_lo");
  const auto hi = r.optional_vec3("region_hi");
  r.note_range("region_lo", "with region_hi: boulders lie wholly in the box (r-z: x bounds r)",
               "m");
  r.note_range("region_hi", "with region_lo", "m");
  if (lo.has_value() != hi.has_value()) {
    r.fail(lo ? "region_hi" : "region_lo", "region_lo and region_hi are given together");
  }
  if (lo) {
    if (!(lo->array() < hi->array()).all())
      r.fail("region_hi", "must exceed region_lo on every axis");
    p.region = Bounds{*lo, *hi};
  }
  p.axisymmetric = scene.solver.geometry == Geometry::axisymmetric;
  p.spacing = host.spacing;
  p.stream = host.name;
  return p;
}

}  // namespace

std::optional<BodySpec> read_boulders(Reader& body, BodySpec& host, Scene& scene,
                                      const MaterialCatalogue& catalogue) {
  body.note_type("boulders", "table");
  toml::table* t = body.subtable("boulders");
  if (t == nullptr) return std::nullopt;
  Reader r(*t, body.key_path("boulders"), body.where("boulders"));
  r.allow({"material", "volume_fraction", "radius_min", "radius_max", "exponent", "seed",
           "region_lo", "region_hi", "damage", "placed", "fraction_placed"});
  r.reject_unknown();
  const bool rz = scene.solver.geometry == Geometry::axisymmetric;
  if (scene.symmetry_axis >= 0 && !rz) {  // r-z sets the axis as its symmetry face
    body.fail("boulders",
              "a random boulder field has no mirror symmetry: remove solver.symmetry_plane (model "
              "the whole body)");
  }
  if (body.has("mass")) {
    body.fail("boulders",
              "is given with the body's mass: the mass would fix the density of the "
              "host before its boulders are cut out; give one of them");
  }

  BodySpec b;
  b.name = host.name + "_boulders";
  b.where = body.where("boulders");
  b.material = read_material(r, catalogue);
  r.note_default("material", "*required*");

  const BoulderParams p = read_params(r, host, scene);
  read_damage(r, b, scene);

  BoulderField field;
  try {
    field = place_boulders(host.shape, p);
  } catch (const BoulderError& e) {
    r.fail(e.key, e.what());
  }
  // Reported in the resolved scene (a value given in the scene, as in a run's scene.toml, is read
  // and replaced).
  (void)r.optional_number("placed");
  (void)r.optional_number("fraction_placed");
  r.note_range("placed", "written by the reader: the number of boulders placed");
  r.note_range("fraction_placed", "written by the reader: the volume fraction reached");
  t->insert_or_assign("placed", static_cast<std::int64_t>(field.set->spheres().size()));
  t->insert_or_assign("fraction_placed", field.fraction());
  scene.notes.push_back(
      fmt::format("body {}: {} boulders (body {}), radius {}-{} m, volume fraction {:.4f} of "
                  "{:.4g} m^3 (asked {}), seed {}{}",
                  host.name, field.set->spheres().size(), b.name, p.radius_min, p.radius_max,
                  field.fraction(), field.host_volume, p.volume_fraction, p.seed,
                  p.axisymmetric ? "; r-z: rings about the axis, spheres on it" : ""));

  host.shape.holes = field.set;
  b.shape.parts = host.shape.parts;
  b.shape.only = field.set;
  b.velocity = host.velocity;
  b.spacing = host.spacing;
  b.energy = host.energy;
  b.driven = host.driven;
  b.lattice_rotation = host.lattice_rotation;
  return b;
}

}  // namespace shatter::scene
