#include "shatter/scene/scene.hpp"

#include <algorithm>
#include <tuple>

#include <fmt/format.h>

#include "scene/document.hpp"
#include "scene/parts.hpp"
#include "scene/ranges.hpp"
#include "shatter/io/columns.hpp"
#include "shatter/io/suggest.hpp"
#include "shatter/material/catalogue_path.hpp"

namespace shatter::scene {
namespace {

// The columns written when the scene does not list them: what the paper's figures and the
// fragment search need.
const std::vector<std::string> kDefaultColumns = {"x",        "y",
                                                  "z",        "vx",
                                                  "vy",       "vz",
                                                  "mass",     "volume0",
                                                  "rho",      "energy",
                                                  "pressure", "peak_pressure",
                                                  "damage",   "plastic_strain",
                                                  "sxx",      "syy",
                                                  "szz",      "sxy",
                                                  "syz",      "sxz",
                                                  "id",       "body"};

// The shipped catalogue, or the scene's `catalogue = "file.toml"` (relative to the scene).
MaterialCatalogue read_catalogue(Reader& root, toml::table& doc,
                                 const std::filesystem::path& base_dir, Scene& scene) {
  MaterialCatalogue catalogue = MaterialCatalogue::builtin();
  scene.catalogue_file = builtin_catalogue_path();
  if (auto file = root.optional_string("catalogue")) {
    const auto path = std::filesystem::absolute(base_dir / *file);
    // Named here: the catalogue loader would report a missing file as a TOML syntax error.
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) {
      root.fail("catalogue", fmt::format("{}: {}", path.string(),
                                         std::filesystem::exists(path, ec)
                                             ? "is not a regular file (a directory?)"
                                             : "no such catalogue file"));
    }
    try {
      catalogue = MaterialCatalogue::load(path);
      scene.catalogue_file = path;
    } catch (const std::exception& e) {
      root.fail("catalogue", e.what());
    }
    // Absolute in the resolved scene, so a resumed run finds it from anywhere.
    doc.insert_or_assign("catalogue", path.string());
  }
  return catalogue;
}

Scene parse(toml::table doc, const std::string& source, const std::vector<std::string>& overrides,
            const std::filesystem::path& base_dir, Points points) {
  for (const auto& o : overrides) apply_override(doc, o);

  Scene scene;
  scene.source = source;
  scene.base_dir = base_dir;
  Reader root(doc, "", source);
  root.allow({"name", "description", "catalogue", "solver", "domain", "body", "impact", "fracture",
              "output", "gravity", "beta"});
  root.reject_unknown();
  scene.name = root.string("name", std::filesystem::path(source).stem().string());
  root.note_default("name", "the file name without .toml");
  root.note_default("body", "*required*");
  root.note_type("body", "table of [body.NAME] tables");
  scene.description = root.string("description", "-");

  const MaterialCatalogue catalogue = read_catalogue(root, doc, base_dir, scene);

  read_solver(root, scene);
  read_domain(root, scene);
  read_gravity(root, scene);
  read_fracture(root, scene);
  const auto impact = read_impact(root, scene);

  toml::table* bodies = root.subtable("body");
  if (bodies == nullptr || bodies->empty()) {
    root.fail("body", "at least one body is required ([body.NAME] with shape and material)");
  }
  if (impact) {
    // Checked before the bodies are read: a misspelt projectile would otherwise be read as an
    // ordinary body and reported as missing its centre.
    std::vector<std::string> names;
    for (auto&& [key, node] : *bodies) names.emplace_back(key.str());
    for (const auto& [role, name, where] :
         {std::tuple{"projectile", impact->projectile, impact->where_projectile},
          std::tuple{"target", impact->target, impact->where_target}}) {
      if (std::find(names.begin(), names.end(), name) == names.end()) {
        throw SceneError(where, std::string("impact.") + role,
                         fmt::format("no body '{}'{} (bodies: {})", name,
                                     io::did_you_mean(name, names), fmt::join(names, ", ")));
      }
    }
  }
  std::vector<BodySpec> boulders;
  for (auto&& [key, node] : *bodies) {
    const std::string name(key.str());
    auto* t = node.as_table();
    if (t == nullptr) {
      Reader b(*bodies, "body");
      b.fail(name, "must be a table ([body." + name + "])");
    }
    Reader b(*t, "body." + name, location(key.source()));
    const bool placed = impact && impact->projectile == name;
    scene.bodies.push_back(read_body(b, name, scene, catalogue, placed));
    if (auto field = read_boulders(b, scene.bodies.back(), scene, catalogue)) {
      boulders.push_back(std::move(*field));
    }
  }
  // Boulder bodies (NAME_boulders) after the bodies of the file, whose ids stay as they were.
  for (BodySpec& field : boulders) {
    for (const BodySpec& other : scene.bodies) {
      if (other.name == field.name) {
        throw SceneError(field.where,
                         "body." + field.name.substr(0, field.name.size() - 9) + ".boulders",
                         fmt::format("its body would be named '{}', which a [body.{}] of the "
                                     "scene already is; rename that body",
                                     field.name, field.name));
      }
    }
    scene.bodies.push_back(std::move(field));
  }
  if (impact) apply_impact(*impact, scene);
  resolve_contact_pairs(scene);
  if (points == Points::fill) fill_and_check_bodies(scene);
  read_beta(root, scene);
  read_output(root, scene);
  scene.resolved = to_toml(doc);
  return scene;
}

}  // namespace

std::size_t Scene::particle_count() const {
  std::size_t n = 0;
  for (const auto& b : bodies) n += b.fill.points.size();
  return n;
}

toml::table& table_or_empty(Reader& parent, const char* key) {
  if (toml::table* t = parent.subtable(key)) return *t;
  parent.table().insert(key, toml::table{});
  return *parent.subtable(key);
}

void read_fracture(Reader& root, Scene& scene) {
  toml::table& t = table_or_empty(root, "fracture");
  Reader r(t, "fracture", root.where("fracture"));
  r.allow({"seed", "threshold", "fragment_method", "fragment_cell", "static_strength"});
  r.reject_unknown();
  const auto seed = r.integer("seed", 1);
  r.note_range("seed", ">= 0");
  if (seed < 0) r.fail("seed", "must be >= 0");
  scene.fracture.seed = static_cast<std::uint64_t>(seed);
  scene.fracture.threshold = r.number("threshold", 0.9);
  r.note_range("threshold", "(0, 1]", "damage");
  if (!(scene.fracture.threshold > 0.0 && scene.fracture.threshold <= 1.0)) {
    r.fail("threshold", fmt::format("must be in (0, 1] (got {})", scene.fracture.threshold));
  }
  scene.fracture.search.method =
      r.choice("fragment_method", "grid_density", {"grid_density", "friends_of_friends"});
  scene.fracture.search.damage_threshold = scene.fracture.threshold;
  scene.fracture.search.cell_size = r.non_negative("fragment_cell", r.number("fragment_cell", 0.0));
  r.note_range("fragment_cell", "0 = twice the mean point spacing", "m");
  // BA95 Sec. 4.4 (friends_of_friends only): the static-strength pre-pass, Pa (0 = off); and,
  // for SPH runs, friends within one smoothing length (the solver's h = h_factor (m/rho)^{1/3}).
  if (r.has("static_strength")) {
    if (scene.fracture.search.method != "friends_of_friends") {
      r.fail("static_strength", "applies only with fragment_method = \"friends_of_friends\"");
    }
    scene.fracture.search.static_strength =
        r.positive("static_strength", r.number("static_strength", 0.0));
  }
  if (scene.method == "sph" && scene.fracture.search.method == "friends_of_friends") {
    scene.fracture.search.smoothing_factor = scene.sph.h_factor;
  }
}

static void read_output_columns(Reader& r, Scene& scene);

void read_output(Reader& root, Scene& scene) {
  toml::table& t = table_or_empty(root, "output");
  Reader r(t, "output", root.where("output"));
  r.allow({"directory", "snapshot_every", "columns", "checkpoint_every", "timeseries_every",
           "progress_every", "fragments", "snapshot_precision", "ss_radius"});
  r.reject_unknown();
  OutputSpec& o = scene.output;
  o.directory = r.string("directory", "out/" + scene.name);
  r.note_default("directory", "`\"out/NAME\"` (NAME: the scene's name)");
  r.note_default("snapshot_every", "end_time / 10");
  r.note_range("snapshot_every", "0 = first and last only", "s");
  r.note_range("checkpoint_every", "0 = at the end only", "s");
  o.snapshot_every =
      r.non_negative("snapshot_every", r.number("snapshot_every", scene.end_time / 10));
  o.checkpoint_every = r.non_negative("checkpoint_every", r.number("checkpoint_every", 0.0));
  for (const char* k : {"snapshot_every", "checkpoint_every"}) {
    const double every =
        std::string_view(k) == "snapshot_every" ? o.snapshot_every : o.checkpoint_every;
    if (every > 0.0 && scene.end_time / every > ranges::kMaxOutputs) {
      r.fail(k, fmt::format("= {} s writes {:.3g} files before end_time = {} s; the limit is "
                            "{:.0e} (a cadence mistake)",
                            every, scene.end_time / every, scene.end_time, ranges::kMaxOutputs));
    }
  }
  o.timeseries_every = r.integer("timeseries_every", 10);
  r.note_range("timeseries_every", ">= 1", "steps");
  r.note_range("progress_every", "", "s (wall clock)");
  if (o.timeseries_every < 1) r.fail("timeseries_every", "must be >= 1 (steps)");
  o.progress_every = r.non_negative("progress_every", r.number("progress_every", 5.0));
  // r-z (issue 31): a point is a ring about the axis; the search links rings in the half-plane
  // and reports bodies of revolution (FragmentSearchSpec::axisymmetric).
  o.fragments = r.boolean("fragments", true);
  scene.fracture.search.axisymmetric = scene.solver.geometry == Geometry::axisymmetric;
  // The pkdgrav hand-off's radii (fragments.ss; docs/outputs.md, "N-body hand-off").
  scene.fracture.search.ss_radius =
      ss_radius_by_name(r.choice("ss_radius", "equal_volume", {"equal_volume", "packing_safe"}));
  // Snapshots only: checkpoints are always binary64 (a resume continues bit for bit).
  o.single_precision = r.choice("snapshot_precision", "double", {"double", "single"}) == "single";
  read_output_columns(r, scene);
}

// output.columns: "default" (with the distension column when a body is porous), "all" or a list
// of names that must include the XDMF geometry.
static void read_output_columns(Reader& r, Scene& scene) {
  OutputSpec& o = scene.output;
  r.note_type("columns", "\"default\", \"all\" or array of column names");
  const toml::node* c = r.table().get("columns");
  r.note_default("columns",
                 "`\"default\"` (positions, velocities, mass, volume0, rho, energy, pressure, "
                 "peak_pressure, damage, plastic_strain, stress, id, body; distension, porosity "
                 "and compaction_heat when a body is porous)");
  if (c == nullptr || (c->is_string() && c->as_string()->get() == "default")) {
    o.columns = kDefaultColumns;
    // A porous body's compaction state (issue 29): the distension alpha = rho_s / rho, from which
    // the porosity is 1 - 1/alpha (docs/outputs.md). Only then: a dense scene has no such column.
    if (std::any_of(scene.bodies.begin(), scene.bodies.end(),
                    [](const BodySpec& b) { return !b.material.porosity.empty(); })) {
      o.columns.emplace_back("distension");
      o.columns.emplace_back("porosity");         // 1 - 1/alpha
      o.columns.emplace_back("compaction_heat");  // the compaction work booked, J/kg
    }
    if (c == nullptr) r.table().insert("columns", "default");
  } else if (c->is_string() && c->as_string()->get() == "all") {
    o.columns.clear();
  } else if (const auto* a = c->as_array()) {
    for (const auto& e : *a) {
      if (!e.is_string()) r.fail("columns", "must be \"default\", \"all\" or an array of names");
      o.columns.push_back(e.as_string()->get());
    }
    try {
      io::select_columns(o.columns);
    } catch (const std::invalid_argument& e) {
      r.fail("columns", e.what());
    }
    for (const char* axis : {"x", "y", "z"}) {
      if (std::find(o.columns.begin(), o.columns.end(), axis) == o.columns.end()) {
        r.fail("columns", fmt::format("must include '{}' (the XDMF geometry)", axis));
      }
    }
  } else {
    r.fail("columns", "must be \"default\", \"all\" or an array of column names");
  }
}

void fill_bodies(Scene& scene) {
  fill_and_check_bodies(scene);
}

Scene load_scene(const std::filesystem::path& file, const std::vector<std::string>& overrides,
                 Points points) {
  return parse(load_document(file), file.string(), overrides, file.parent_path(), points);
}

Scene parse_scene(std::string_view text, const std::string& source,
                  const std::vector<std::string>& overrides, const std::filesystem::path& base_dir,
                  Points points) {
  return parse(parse_document(text, source, base_dir), source, overrides, base_dir, points);
}

}  // namespace shatter::scene
