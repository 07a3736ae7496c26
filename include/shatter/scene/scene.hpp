#pragma once
// A scene: bodies (geometry, material, velocity, spacing), solver settings, damage, output. Read
// from TOML; every key is checked and an error names the file, line and key (SceneError).
//
// File layout (scenes/*.toml are the worked examples; docs/scenes.md lists every key, generated
// from the reader by `shatter scene-reference`):
//   name, description          text
//   extends = "base.toml"      start from another scene and override it
//   catalogue = "file.toml"    material catalogue (default: the one shipped, data/materials.toml)
//   [solver]                   method, shape, cell_size, cfl, end_time, dt_max, dt_min, gravity,
//                              symmetry_plane, reorder_interval, dt_floor_ratio, contact,
//                              friction, [[solver.contact_pair]], [solver.viscosity],
//                              [solver.sph] (h_factor, alpha, beta)
//   [domain]                   lo, hi, boundary, x_lo, x_hi, y_lo, y_hi, z_lo, z_hi
//   [body.NAME]                shape (sphere, ellipsoid, box, cylinder, mesh, union) + its keys,
//                              material, velocity, spacing, points_per_cell,
//                              energy, mass, [body.NAME.damage], [body.NAME.boulders]
//   [impact]                   projectile, target, speed, angle, direction, offset, gap
//   [fracture]                 seed, threshold, fragment_method, fragment_cell, static_strength
//   [output]                   directory, snapshot_every, columns, checkpoint_every,
//                              timeseries_every, progress_every, fragments

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "shatter/core/config.hpp"
#include "shatter/fracture/beta.hpp"
#include "shatter/fracture/flaws.hpp"
#include "shatter/fracture/fragments.hpp"
#include "shatter/material/catalogue.hpp"
#include "shatter/scene/lattice.hpp"
#include "shatter/scene/scene_error.hpp"
#include "shatter/scene/shapes.hpp"
#include "shatter/sph/config.hpp"

namespace shatter::scene {

struct BodySpec {
  std::string name;
  std::string where;  // "file:line" of the body's table
  Shape shape;
  MaterialSpec material;  // catalogue entry with the scene's overrides applied
  DamageSpec damage;
  std::optional<FlawSpec> flaws;  // set when the damage model needs explicit flaws
  Vec3 velocity = Vec3::Zero();   // m/s
  double spacing = 0.0;           // m, between neighbouring points (also size0 for uGIMP)
  double energy = 0.0;            // J/kg, initial specific internal energy
  // Prescribed velocity (`driven`): the body keeps its initial velocity for the whole run and
  // drags what it touches (src/mpm/driven.hpp; SPH: SphSolver::set_velocity_constraint).
  bool driven = false;
  // Turns the point lattice about the origin (`lattice_rotation`); identity: aligned with the grid.
  Eigen::Matrix3d lattice_rotation = Eigen::Matrix3d::Identity();
  LatticeFill fill;  // the body's points (half model clipped)
};

// What the [impact] helper derived, for the log and the resolved scene.
struct ImpactSummary {
  bool used = false;
  std::string projectile, target;
  double speed = 0.0;      // m/s
  double angle_deg = 0.0;  // between velocity and surface normal at the impact point
  Vec3 impact_point = Vec3::Zero();
  Vec3 projectile_centre = Vec3::Zero();
};

struct OutputSpec {
  std::filesystem::path directory;
  double snapshot_every = 0.0;         // s of simulated time; 0 = first and last only
  std::vector<std::string> columns;    // column names; empty = every registered column
  double checkpoint_every = 0.0;       // s of simulated time; 0 = at the end only
  std::int64_t timeseries_every = 10;  // steps
  double progress_every = 5.0;         // s of wall time between progress lines
  bool fragments = true;               // fragment catalogue of the last snapshot
  bool single_precision = false;       // snapshot_precision = "single": binary32 snapshots
};

struct FractureSettings {
  std::uint64_t seed = 1;
  double threshold = 0.9;  // failed = D >= threshold (MPM paper Sec. 4.1.1)
  FragmentSearchSpec search;
};

// One [[solver.contact_pair]] entry as read (body names are resolved once bodies are known).
struct ContactPairSpec {
  std::string a, b;
  double friction = 0.0;
  std::string where, key;  // for errors: "file:line" and the dotted key
};

struct Scene {
  std::string name;
  std::string description;
  std::string source;                    // file the scene came from (or "<text>")
  std::filesystem::path base_dir;        // where relative file names (catalogue, meshes) are found
  std::filesystem::path catalogue_file;  // the material catalogue the bodies were read from
  SolverConfig solver;
  std::string method = "mpm";  // solver.method: "mpm" (default) or "sph"
  sph::SphConfig sph;          // [solver.sph], read when method = "sph"
  double end_time = 0.0;       // s
  // The run stops (exit 3) when the stable step falls below this times the first step's
  // (solver.dt_floor_ratio; 0 = never): a collapse that would take as many times the steps.
  double dt_floor_ratio = 1e-4;
  int symmetry_axis = -1;  // 0, 1, 2 = symmetry plane x = 0, y = 0, z = 0 (positive half kept)
  std::vector<BodySpec> bodies;
  std::vector<ContactPairSpec> contact_pairs;  // already in solver.contact.pairs as ids
  ImpactSummary impact;
  FractureSettings fracture;
  OutputSpec output;
  std::optional<BetaSpec> beta;  // [beta]: beta(t) in the time series (issue 32)
  std::string resolved;          // the scene as TOML after extends and --set, defaults written out
  // What the reader derived that the user should see (`shatter check` prints them): the boulder
  // fields placed ([body.NAME.boulders]).
  std::vector<std::string> notes;

  std::size_t particle_count() const;
};

// Whether reading a scene fills its bodies with points (the default) or leaves that to
// fill_bodies, so that the size of the run can be checked before anything is allocated
// (include/shatter/scene/estimate.hpp).
enum class Points { fill, defer };

// Fills every body with points (BodySpec::fill) and checks them against the domain and each
// other; throws SceneError. What load_scene does unless given Points::defer.
void fill_bodies(Scene& scene);

// Reads a scene file. `overrides` are "dotted.key=value" strings (--set), applied after the
// file (and any file it extends) was read; the value is TOML ("0.5", "\"granite\"", "[0,0,1]")
// or, if it does not parse as TOML, a bare string. Throws SceneError.
Scene load_scene(const std::filesystem::path& file, const std::vector<std::string>& overrides = {},
                 Points points = Points::fill);

// Same from text (`source` names it in messages); `base_dir` resolves relative paths (extends,
// catalogue).
Scene parse_scene(std::string_view text, const std::string& source,
                  const std::vector<std::string>& overrides = {},
                  const std::filesystem::path& base_dir = ".", Points points = Points::fill);

}  // namespace shatter::scene
