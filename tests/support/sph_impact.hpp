#pragma once
// Scenes the SPH unit tests share. The small impact: a basalt sphere (12 mm radius, 2 mm spacing,
// ~900 points; Tillotson, linear hardening) hit by a 4 mm nylon sphere at 3.2 km/s, 30 degrees:
// shocks, plasticity and (with damage) fracture in a few dozen steps. The tests differ in a few
// lines, which are the arguments, so that each test shows what it changes.

#include <string>
#include <string_view>

namespace shatter::test {

// The lines a test changes. flaws: empty for no damage, else Grady-Kipp (m = 8.5,
// k = 3e39 m^-3) with this flaw line, e.g. "total_flaws = 1.0e9\n" (the MPM paper's
// resolution-independent flaws) or "explicit_flaws = 1\n" (BA95 Eq. 20).
struct SphImpactLines {
  std::string_view solver = {};  // extra lines of [solver], e.g. symmetry_plane = "z"
  std::string_view flaws = {};
  std::string_view tables = {};  // tables appended at the end, e.g. [fracture]
};

inline std::string sph_impact_scene(const SphImpactLines& lines) {
  std::string text = "[solver]\nmethod = \"sph\"\ncell_size = 4.0e-3\nend_time = 1.0\n";
  text += lines.solver;
  text += R"(
[body.target]
shape = "sphere"
centre = [0.0, 0.0, 0.0]
radius = 0.012
material = "basalt"
)";
  if (!lines.flaws.empty()) {
    text += "[body.target.damage]\nmodel = \"grady_kipp\"\nweibull_m = 8.5\nweibull_k = 3.0e39\n";
    text += lines.flaws;
  }
  text += R"(
[body.projectile]
shape = "sphere"
radius = 4.0e-3
material = "nylon"
[impact]
projectile = "projectile"
target = "target"
speed = 3200.0
angle = 30.0
)";
  text += lines.tables;
  return text;
}

// Two elastic spheres (verification catalogue: E = 1000 Pa, Poisson 0.3, rho = 1000 kg/m^3,
// c_p = 1.16 m/s) meeting head-on at 0.35 m/s, 0.05 m spacing (~270 points each); parse with the
// verification catalogue's directory.
inline constexpr const char* kSphCollidingSpheres = R"(
catalogue = "materials.toml"
[solver]
method = "sph"
cell_size = 0.1
end_time = 1.0
[body.a]
shape = "sphere"
centre = [0.3, 0.3, 0.3]
radius = 0.2
material = "sphere_elastic"
velocity = [0.1, 0.1, 0.1]
[body.b]
shape = "sphere"
centre = [0.56, 0.56, 0.56]
radius = 0.2
material = "sphere_elastic"
velocity = [-0.1, -0.1, -0.1]
)";

}  // namespace shatter::test
