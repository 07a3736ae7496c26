#include <cmath>
#include <filesystem>
#include <numbers>

#include <Eigen/Geometry>

#include <fmt/format.h>

#include "scene/parts.hpp"
#include "scene/ranges.hpp"
#include "shatter/io/suggest.hpp"
#include "shatter/scene/mesh.hpp"

namespace shatter::scene {
namespace {

const std::vector<std::string> kShapeKinds = {"sphere",   "ellipsoid", "box",
                                              "cylinder", "mesh",      "union"};
const std::vector<std::string> kBodyKeys = {
    "shape", "material", "velocity",         "spacing", "points_per_cell", "energy",
    "mass",  "damage",   "lattice_rotation", "driven",  "porosity",        "boulders"};
const std::vector<std::string> kMaterialModelKeys = {"eos", "strength"};

std::vector<std::string> shape_keys(const std::string& kind) {
  if (kind == "sphere") return {"centre", "radius"};
  if (kind == "ellipsoid") return {"centre", "semi_axes"};
  if (kind == "box") return {"lo", "hi"};
  if (kind == "cylinder") return {"centre", "axis", "radius", "length"};
  if (kind == "mesh") return {"file", "scale", "rotation", "position"};
  return {"parts"};
}

// A primitive from `r` (a body table or one element of a union's parts). The centre may be left
// out when the impact helper places the body; it is then set later.
// A position (|coordinate| bounded) and a size (a length in range) of a shape.
Vec3 position(Reader& r, std::string_view key) {
  const Vec3 v = r.vec3(key);
  r.within(key, v.cwiseAbs().maxCoeff(), 0.0, ranges::kMaxCoordinate, "m (|coordinate|)",
           ranges::kCoordinateReason);
  return v;
}
double size(Reader& r, std::string_view key, double v) {
  r.positive(key, v);
  return r.within(key, v, ranges::kMinLength, ranges::kMaxLength, "m", ranges::kLengthReason);
}

// Rotations about x, then y, then z by the angles (degrees, fixed axes) of a `rotation`-like key,
// checked to lie within a full turn.
Eigen::Matrix3d read_rotation(Reader& r, std::string_view key) {
  const Vec3 angles = r.vec3(key, Vec3::Zero());
  r.within(key, angles.cwiseAbs().maxCoeff(), 0.0, 360.0, "degrees (|angle|)", "a full turn");
  const double deg = std::numbers::pi / 180.0;
  return (Eigen::AngleAxisd(angles.z() * deg, Vec3::UnitZ()) *
          Eigen::AngleAxisd(angles.y() * deg, Vec3::UnitY()) *
          Eigen::AngleAxisd(angles.x() * deg, Vec3::UnitX()))
      .toRotationMatrix();
}

// A closed triangle mesh (OBJ or STL) scaled, rotated and placed: x' = position + R (scale x),
// with R the rotations about x, then y, then z by the angles in `rotation` (degrees, fixed axes).
Mesh read_mesh_shape(Reader& r, const std::filesystem::path& base_dir) {
  const std::filesystem::path file =
      std::filesystem::absolute(base_dir / std::filesystem::path(r.string("file")));
  const double scale = r.positive("scale", r.number("scale", 1.0));
  r.note_range("scale", "", "m per mesh unit");
  const Eigen::Matrix3d rotation = read_rotation(r, "rotation");
  const Vec3 shift = r.vec3("position", Vec3::Zero());
  r.within("position", shift.cwiseAbs().maxCoeff(), 0.0, ranges::kMaxCoordinate, "m (|coordinate|)",
           ranges::kCoordinateReason);
  TriangleMesh mesh;
  try {
    mesh = read_mesh(file);  // its messages name the file (and line)
  } catch (const std::invalid_argument& e) {
    r.fail("file", e.what());
  }
  try {
    check_closed(mesh);
  } catch (const std::invalid_argument& e) {
    r.fail("file", fmt::format("{}: {}", file.string(), e.what()));
  }
  for (Vec3& v : mesh.vertices) v = shift + rotation * (scale * v);
  // Absolute in the resolved scene, so a resumed run finds the file from anywhere.
  r.table().insert_or_assign("file", file.string());
  auto solid = std::make_shared<const MeshSolid>(std::move(mesh));
  // Overlapping shells are filled once (winding number), but the volume and the intent are
  // unclear: the user is told (a 32^3 probe of the bounding box; a thinner overlap is still
  // filled correctly).
  if (const auto p = solid->find_overlap(32)) {
    r.fail("file", fmt::format("{}: the surface encloses the point {} more than once (overlapping "
                               "shells or a self-intersecting surface); merge the shells into one "
                               "surface in a mesh editor (a boolean union)",
                               file.string(),
                               fmt::format("({:.6g}, {:.6g}, {:.6g}) m", p->x(), p->y(), p->z())));
  }
  return Mesh{std::move(solid)};
}

Primitive read_primitive(Reader& r, const std::string& kind, bool centre_optional,
                         const std::filesystem::path& base_dir) {
  if (kind == "mesh") return read_mesh_shape(r, base_dir);
  auto centre = [&] {
    if (centre_optional) return Vec3::Zero().eval();
    return position(r, "centre");
  };
  if (kind == "sphere") {
    Sphere s;
    s.centre = centre();
    s.radius = size(r, "radius", r.number("radius"));
    return s;
  }
  if (kind == "ellipsoid") {
    Ellipsoid e;
    e.centre = centre();
    e.semi_axes = r.vec3("semi_axes");
    for (int a = 0; a < 3; ++a) size(r, "semi_axes", e.semi_axes[a]);
    return e;
  }
  if (kind == "box") {
    Box b;
    b.lo = position(r, "lo");
    b.hi = position(r, "hi");
    if (!(b.lo.array() < b.hi.array()).all()) r.fail("hi", "must exceed lo on every axis");
    return b;
  }
  Cylinder c;
  c.centre = centre();
  const Vec3 axis = r.vec3("axis", Vec3::UnitZ());
  if (!(axis.norm() > 0.0)) r.fail("axis", "must not be the zero vector");
  c.axis = axis.normalized();
  c.radius = size(r, "radius", r.number("radius"));
  c.length = size(r, "length", r.number("length"));
  return c;
}

Shape read_shape(Reader& r, bool placed_by_impact, const std::filesystem::path& base_dir) {
  const std::string kind = r.choice("shape", "", kShapeKinds);
  std::vector<std::string> allowed = kBodyKeys;
  const auto keys = shape_keys(kind);
  allowed.insert(allowed.end(), keys.begin(), keys.end());
  r.allow(allowed);
  r.reject_unknown();
  if (placed_by_impact) {
    if (kind != "sphere") r.fail("shape", "the [impact] projectile must be a sphere");
    if (r.has("centre")) r.fail("centre", "is set by [impact]; remove it here");
    if (r.has("velocity")) r.fail("velocity", "is set by [impact] (speed); remove it here");
  }
  Shape shape;
  if (kind != "union") {
    shape.parts.push_back(read_primitive(r, kind, placed_by_impact, base_dir));
    return shape;
  }
  r.note_type("parts", "array of tables (shape and its keys)");
  const toml::node* parts = r.table().get("parts");
  if (parts == nullptr) r.fail("parts", "is required for a union (an array of shape tables)");
  const auto* array = parts->as_array();
  if (array == nullptr || array->empty()) r.fail("parts", "must be a non-empty array of tables");
  for (std::size_t i = 0; i < array->size(); ++i) {
    auto* part = const_cast<toml::node*>(array->get(i))->as_table();  // NOLINT: our document
    if (part == nullptr) r.fail("parts", fmt::format("element {} is not a table", i));
    Reader p(*part, fmt::format("{}[{}]", r.key_path("parts"), i), r.where("parts"));
    const std::string pk =
        p.choice("shape", "", {"sphere", "ellipsoid", "box", "cylinder", "mesh"});
    auto pkeys = shape_keys(pk);
    pkeys.push_back("shape");
    p.allow(pkeys);
    p.reject_unknown();
    shape.parts.push_back(read_primitive(p, pk, false, base_dir));
  }
  return shape;
}

// The key of `table` an error message from the material library is about (it quotes it), so the
// error can point at that key's line; empty when none is named.
std::string key_named_in(const std::string& message, const toml::table& table) {
  for (const auto& [k, v] : table) {
    if (message.find(fmt::format("'{}'", k.str())) != std::string::npos)
      return std::string(k.str());
  }
  return {};
}

}  // namespace

MaterialSpec read_material(Reader& body, const MaterialCatalogue& catalogue) {
  body.note_type("material", "string or table");
  const toml::node* n = body.table().get("material");
  if (n == nullptr) body.fail("material", "is required but missing (a catalogue name)");
  toml::table* overrides = n->is_table() ? body.subtable("material") : nullptr;
  std::string name;
  std::optional<Reader> r;
  if (overrides != nullptr) {
    r.emplace(*overrides, body.key_path("material"), body.where("material"));
    name = r->string("name");
  } else {
    name = body.string("material");
  }
  if (!catalogue.contains(name)) {
    const std::string key = overrides ? "name" : "material";
    const std::string msg =
        fmt::format("unknown material '{}'{} (catalogue: {})", name,
                    io::did_you_mean(name, catalogue.names()), fmt::join(catalogue.names(), ", "));
    if (r) r->fail(key, msg);
    body.fail(key, msg);
  }
  MaterialSpec spec = catalogue.get(name);
  if (!r) return spec;

  // Overrides: model names as strings, parameters as numbers; the material library's validator
  // rejects parameters the models do not know.
  for (auto&& [k, v] : *overrides) {
    const std::string key(k.str());
    if (key == "name") continue;
    if (key == "eos" || key == "strength") {
      (key == "eos" ? spec.eos : spec.strength) = r->string(key);
    } else if (key == "source") {
      spec.source = r->string(key);
    } else {
      spec.params[key] = r->number(key);
    }
  }
  return spec;
}

namespace {

double young_modulus(const MaterialSpec& m) {
  if (m.params.count("young")) return m.params.at("young");
  if (m.params.count("shear_modulus") && m.params.count("bulk_modulus")) {
    const double g = m.params.at("shear_modulus"), k = m.params.at("bulk_modulus");
    return 9.0 * k * g / (3.0 * k + g);
  }
  return 0.0;
}

// The body's initial velocity, whether it is driven, and its specific internal energy.
void read_motion(Reader& r, BodySpec& b, bool placed_by_impact) {
  if (!placed_by_impact) b.velocity = r.vec3("velocity", Vec3::Zero());
  r.within("velocity", b.velocity.norm(), 0.0, ranges::kMaxSpeed, "m/s (speed)",
           ranges::kSpeedReason);
  b.driven = r.boolean("driven", false);
  r.note_range("driven", "true: the body keeps its initial velocity (a grip, a piston)");
  if (b.driven && placed_by_impact) {
    r.fail("driven",
           "the [impact] projectile cannot be driven (it is placed and launched by "
           "[impact]; give it a [body] velocity instead)");
  }
  b.energy = r.non_negative("energy", r.number("energy", 0.0));
  r.within("energy", b.energy, 0.0, ranges::kMaxSpecificEnergy, "J/kg", ranges::kEnergyReason);
}

// The point spacing: given, or cell_size / points_per_cell.
void read_spacing(Reader& r, BodySpec& b, const Scene& scene) {
  if (r.has("spacing") && r.has("points_per_cell")) {
    r.fail("points_per_cell", "give spacing or points_per_cell, not both");
  }
  r.note_default("spacing", "cell_size / points_per_cell");
  r.note_range("spacing", "not with points_per_cell");
  if (r.has("spacing")) {
    b.spacing = size(r, "spacing", r.number("spacing"));
  } else {
    const auto ppc = r.integer("points_per_cell", 2);
    r.note_range("points_per_cell", ">= 1; spacing = cell_size / points_per_cell");
    if (ppc < 1) r.fail("points_per_cell", fmt::format("must be >= 1 (got {})", ppc));
    b.spacing = scene.solver.cell_size / static_cast<double>(ppc);
  }
}

// Refused before the lattice is filled: a spacing far below the body's size would take hours
// and all memory to find out.
void check_point_count(Reader& r, const BodySpec& b) {
  const double volume =
      b.shape.exact_volume().value_or((b.shape.bounds().hi - b.shape.bounds().lo).prod());
  const double points = volume / (b.spacing * b.spacing * b.spacing);
  if (points > ranges::kMaxPoints) {
    r.fail(r.has("spacing")           ? "spacing"
           : r.has("points_per_cell") ? "points_per_cell"
                                      : "shape",
           fmt::format("gives about {:.3g} points for this body (spacing {} m, volume {:.3g} "
                       "m^3); the limit is {:.0e} (~0.5 kB each)",
                       points, b.spacing, volume, ranges::kMaxPoints));
  }
}

// body.porosity: the body's initial porosity phi = 1 - 1/alpha0 (issue 29), in place of the
// porous material's alpha0, so one catalogue material serves targets of any porosity, as iSALE's
// per-object initial porosity (OBJPOR) does; the bulk density is then rho_s (1 - phi) and the
// crush curve starts at alpha0 = 1 / (1 - phi) (W06 Eqs. 8-10; JBM08 Eq. 8). Porosity rather
// than distension: it is what the sources and the asteroid literature quote (rubble piles "20-60%
// porous").
void read_porosity(Reader& r, BodySpec& b) {
  r.note_range("porosity", "[0, 0.99]; a porous material only; sets alpha0 = 1 / (1 - porosity)");
  r.note_default("porosity", "the material's alpha0");
  const auto phi = r.optional_number("porosity");
  if (!phi) return;
  if (b.material.porosity.empty()) {
    r.fail("porosity", fmt::format("material '{}' is not porous (it has no compaction model): "
                                   "use a porous material (e.g. porous_basalt, regolith) or "
                                   "remove the key",
                                   b.material.name));
  }
  if (!(*phi >= 0.0 && *phi <= 0.99)) {
    r.fail("porosity",
           fmt::format("must be in [0, 0.99] (the pore volume fraction; got {})", *phi));
  }
  const toml::node* m = r.table().get("material");
  if (m != nullptr && m->is_table() && m->as_table()->contains("alpha0")) {
    r.fail("porosity", "is given with the material's alpha0 override: give one of them");
  }
  b.material.params["alpha0"] = 1.0 / (1.0 - *phi);
}

// body.mass (sets rho0), then the material's own checks, each refusal naming the key it concerns.
void read_mass_and_validate(Reader& r, BodySpec& b) {
  // Mass given: the density changes, the volume stays (MPM paper Table 2, projectile mass). The
  // mass is the body's, so it fixes the bulk density mass / V; a porous material's rho0 is its
  // matrix density, rho_s = alpha0 mass / V (alpha0 after body.porosity, read before this).
  r.note_range("mass", "", "kg");
  if (auto mass = r.optional_number("mass")) {
    r.positive("mass", *mass);
    const double v = b.shape.exact_volume().value_or(
        fill_lattice(b.shape, b.spacing, -1, b.lattice_rotation).volume);
    const auto a0 = b.material.params.find("alpha0");
    const double alpha0 =
        b.material.porosity.empty() || a0 == b.material.params.end() ? 1.0 : a0->second;
    b.material.params["rho0"] = alpha0 * *mass / v;
  }
  try {
    validate(b.material);
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    if (toml::table* o = r.table().get("material")->is_table() ? r.subtable("material") : nullptr) {
      Reader m(*o, r.key_path("material"), r.where("material"));
      const std::string k = key_named_in(msg, *o);
      m.fail(k.empty() ? "name" : k, msg);
    }
    r.fail(r.has("mass") && msg.find("rho0") != std::string::npos ? "mass" : "material", msg);
  }
}

}  // namespace

// [body.NAME.damage]: the damage model and its parameters (flaws drawn for grady_kipp).
void read_damage(Reader& r, BodySpec& b, const Scene& scene) {
  toml::table* damage = r.subtable("damage");
  if (damage != nullptr) {
    Reader d(*damage, r.key_path("damage"), r.where("damage"));
    b.damage.model = d.string("model", "none");
    for (auto&& [k, v] : *damage) {
      const std::string key(k.str());
      if (key == "model") continue;
      if (key == "coupling") {
        b.damage.coupling = d.string(key);  // damage-stress coupling, validated by make_material
        continue;
      }
      // Parameters are numbers; a string here is most likely a misspelt `model` (found by
      // tests/fuzz: "mdoel: must be a number" did not say what was wrong).
      if (v.is_string()) {
        d.fail(key,
               "is a string, so not a damage parameter (those are numbers); the model is "
               "chosen with the key 'model' (and its damage-stress coupling with 'coupling')");
      }
      b.damage.params[key] = d.number(key);
    }
    try {
      make_material(b.material, b.damage);  // validates the damage model and its parameters
      if (b.damage.model == "grady_kipp") {
        b.flaws = flaw_spec_from_params(b.damage.params, young_modulus(b.material));
        if (!b.damage.params.count("seed")) b.flaws->seed = scene.fracture.seed;
      }
    } catch (const std::invalid_argument& e) {
      const std::string k = key_named_in(e.what(), *damage);
      d.fail(k.empty() ? "model" : k, e.what());
    }
  } else {
    try {
      make_material(b.material, b.damage);
    } catch (const std::invalid_argument& e) {
      r.fail("material", e.what());
    }
  }
}

BodySpec read_body(Reader& r, const std::string& name, const Scene& scene,
                   const MaterialCatalogue& catalogue, bool placed_by_impact) {
  BodySpec b;
  b.name = name;
  b.where = r.where("shape");
  b.shape = read_shape(r, placed_by_impact, scene.base_dir);
  b.material = read_material(r, catalogue);
  read_porosity(r, b);
  read_motion(r, b, placed_by_impact);
  read_spacing(r, b, scene);
  // The point lattice turned off the grid's axes about the origin (MPM paper Sec. 4.1.1 aligns
  // it; docs/validation-lab-impact.md, "Grid imprinting": an aligned lattice prints cracks along
  // the grid axes). A symmetry plane allows turns about its normal only (bodies_check.cpp).
  r.note_range("lattice_rotation",
               "about x, then y, then z (fixed axes), through the origin; with a symmetry plane "
               "only its normal's angle",
               "degrees");
  b.lattice_rotation = read_rotation(r, "lattice_rotation");
  check_point_count(r, b);
  read_mass_and_validate(r, b);
  read_damage(r, b, scene);
  return b;
}

}  // namespace shatter::scene
