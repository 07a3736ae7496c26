#include "shatter/scene/estimate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>

#include <fmt/format.h>

#include "scene/parts.hpp"
#include "shatter/scene/build.hpp"

namespace shatter::scene {
namespace {

// Peak resident bytes per point, per 8-byte particle column. Measured with /usr/bin/time on
// scenes/lab-impact-coarse.toml (1 thread, one snapshot at the start and end) at 1.1e5 and
// 2.6e5 points (cell_size 1.6 and 1.2 mm): the peak grew by 1755 B per point, with 45 columns
// registered, 4.9 times the columns' 360 B (1931 B with main 74ffd54, before the step retake
// copied only the 25 columns a step writes; issue 12). The rest: the retake copy
// (Simulation::step), the stencil rows, the lattice fill, the sparse grid, flaws, sort buffers
// and the snapshot's column buffers.
constexpr double kBytesPerColumnByte = 4.9;
// Fixed cost of the process (libraries, TBB, HDF5), the peak RSS of the tiny scene (2200 points).
constexpr double kBaseBytes = 22.0e6;
// Point-steps per second on one core, whole MUSL step with EOS, strength and Grady–Kipp damage:
// scenes/lab-impact-coarse.toml at 2.6e5 points, 16 steps in 3.6 s wall including set-up, 1
// thread (1.2e6; docs/performance.md's elastic step alone runs 2.6e6 per CPU-second).
constexpr double kPointStepsPerCoreSecond = 1.2e6;

// The fraction of a body's bounds on the kept side of the symmetry plane.
double kept_fraction(const Shape& shape, int axis) {
  if (axis < 0) return 1.0;
  const Bounds b = shape.bounds();
  if (b.lo[axis] >= 0.0) return 1.0;
  if (b.hi[axis] <= 0.0) return 0.0;
  return b.hi[axis] / (b.hi[axis] - b.lo[axis]);
}

bool rz(const Scene& scene) {
  return scene.solver.geometry == Geometry::axisymmetric;
}

// Calls visit(point) for each point the body's fill would create: the 3-D lattice, or the r-z
// half-plane's (fill_lattice_rz).
void each_point(const Scene& scene, const BodySpec& b,
                const std::function<void(const Vec3&)>& visit) {
  if (rz(scene)) {
    for_each_lattice_point_rz(b.shape, b.spacing, visit);
  } else {
    for_each_lattice_point(b.shape, b.spacing, scene.symmetry_axis, visit, b.lattice_rotation);
  }
}

}  // namespace

std::vector<BodyEstimate> estimate_points(const Scene& scene) {
  std::vector<BodyEstimate> out;
  for (const BodySpec& b : scene.bodies) {
    if (rz(scene)) {  // the r-z plane's points are few: counted
      double n = 0;
      for_each_lattice_point_rz(b.shape, b.spacing, [&](const Vec3&) { n += 1; });
      out.push_back({b.name, n, false});
      continue;
    }
    const Bounds bb = b.shape.bounds();
    const double volume = b.shape.exact_volume().value_or((bb.hi - bb.lo).prod());
    const double s3 = b.spacing * b.spacing * b.spacing;
    out.push_back({b.name, volume / s3 * kept_fraction(b.shape, scene.symmetry_axis), false});
  }
  return out;
}

std::vector<BodyEstimate> count_and_check_points(const Scene& scene) {
  const Domain& d = scene.solver.domain;
  std::vector<BodyEstimate> out;
  for (const BodySpec& b : scene.bodies) {
    LatticeCount c;
    if (rz(scene)) check_axisymmetric_body(b);
    check_lattice_rotation(scene, b);
    each_point(scene, b, [&](const Vec3& p) {
      ++c.points;
      c.lo = c.lo.cwiseMin(p);
      c.hi = c.hi.cwiseMax(p);
    });
    if (c.points == 0) {
      throw SceneError(b.where, "body." + b.name, "has no points: smaller than its spacing");
    }
    const double h = 0.5 * b.spacing;
    if ((c.lo.array() - h < d.lo.array()).any() || (c.hi.array() + h > d.hi.array()).any()) {
      throw SceneError(b.where, "body." + b.name,
                       fmt::format("extends outside the domain (points from [{}, {}, {}] to [{}, "
                                   "{}, {}] m; domain lo [{}, {}, {}], hi [{}, {}, {}])",
                                   c.lo.x(), c.lo.y(), c.lo.z(), c.hi.x(), c.hi.y(), c.hi.z(),
                                   d.lo.x(), d.lo.y(), d.lo.z(), d.hi.x(), d.hi.y(), d.hi.z()));
    }
    out.push_back({b.name, static_cast<double>(c.points), true});
  }
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    for (std::size_t j = i + 1; j < scene.bodies.size(); ++j) {
      const BodySpec& a = scene.bodies[i];
      const BodySpec& b = scene.bodies[j];
      if (!a.shape.bounds().intersects(b.shape.bounds())) continue;
      std::size_t inside = 0;
      each_point(scene, b, [&](const Vec3& p) { inside += a.shape.contains(p) ? 1 : 0; });
      each_point(scene, a, [&](const Vec3& p) { inside += b.shape.contains(p) ? 1 : 0; });
      if (inside > 0) {
        throw SceneError(
            b.where, "body." + b.name,
            fmt::format("overlaps body '{}' ({} points lie inside both)", a.name, inside));
      }
    }
  }
  return out;
}

RunEstimate estimate_run(const Scene& scene, std::vector<BodyEstimate> bodies) {
  RunEstimate e;
  e.bodies = std::move(bodies);
  for (const auto& b : e.bodies) e.points += b.points;

  // The flaw count must cover every point (MPM paper Sec. 3.3: each point draws from n_tot
  // flaws); build() refuses it otherwise, after the fill. A body cut by the symmetry plane draws
  // for both halves (build.cpp, flaw_copies).
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const BodySpec& b = scene.bodies[i];
    if (!b.flaws || b.flaws->scheme != "resolution_independent") continue;
    const int a = scene.symmetry_axis;
    const double copies = a >= 0 && b.shape.bounds().lo[a] < b.spacing ? 2.0 : 1.0;
    const double n_p = copies * e.bodies[i].points;
    if (b.flaws->total_flaws < n_p) {
      throw SceneError(b.where, "body." + b.name + ".damage.total_flaws",
                       fmt::format("= {:g} is below the body's {:.4g} points{} (each point draws "
                                   "its flaws from them, MPM paper Sec. 3.3)",
                                   b.flaws->total_flaws, n_p,
                                   copies > 1.0 ? " (both halves of the half model)" : ""));
    }
  }

  // One point per body, in the body's initial state (its flaws drawn for that one point check
  // the flaw parameters).
  Scene sample = scene;
  for (BodySpec& b : sample.bodies) {
    const Bounds bb = b.shape.bounds();
    Vec3 p = 0.5 * (bb.lo + bb.hi);
    if (scene.symmetry_axis >= 0) {
      p[scene.symmetry_axis] = std::max(p[scene.symmetry_axis], 0.5 * b.spacing);
    }
    // Inside the domain (the bodies are checked against it when they are filled).
    const Domain& d = scene.solver.domain;
    for (int a = 0; a < 3; ++a) {
      if (std::isfinite(d.lo[a]) && std::isfinite(d.hi[a]) && d.hi[a] - d.lo[a] > b.spacing) {
        p[a] = std::clamp(p[a], d.lo[a] + 0.5 * b.spacing, d.hi[a] - 0.5 * b.spacing);
      }
    }
    b.fill.points = {p};
    b.fill.volume = b.spacing * b.spacing * b.spacing;
  }
  BuiltScene built = build(sample);
  const auto solver = make_solver(sample, std::move(built.particles), built.materials, 1);
  const ParticleStore& P = solver->particles();
  for (std::size_t f = 0; f < kFieldCount; ++f) e.columns += P.has(static_cast<Field>(f)) ? 1 : 0;
  for (std::size_t f = 0; f < kIFieldCount; ++f) {
    e.columns += P.has(static_cast<IField>(f)) ? 1 : 0;
  }
  e.bytes_per_point = kBytesPerColumnByte * 8.0 * static_cast<double>(e.columns);
  e.bytes = kBaseBytes + e.points * e.bytes_per_point;
  e.dt_first = solver->clock().dt;
  e.steps = e.dt_first > 0.0 ? std::ceil(scene.end_time / e.dt_first) : 0.0;
  e.seconds_per_core = e.steps * e.points / kPointStepsPerCoreSecond;
  return e;
}

std::optional<double> available_memory() {
  if (const char* limit = std::getenv("SHATTER_MEMORY_LIMIT")) {
    char* end = nullptr;
    const double v = std::strtod(limit, &end);
    if (end != limit && v > 0.0) return v;
  }
  std::optional<double> avail;
  std::ifstream meminfo("/proc/meminfo");
  std::string line;
  while (std::getline(meminfo, line)) {
    if (line.rfind("MemAvailable:", 0) == 0) {
      std::istringstream in(line.substr(13));
      double kb = 0.0;
      if (in >> kb) avail = kb * 1024.0;
    }
  }
  // A container's own limit (cgroup v2) may be lower than the host's free memory.
  std::ifstream max("/sys/fs/cgroup/memory.max"), current("/sys/fs/cgroup/memory.current");
  std::string m;
  double used = 0.0;
  if (max >> m && m != "max" && current >> used) {
    const double room = std::strtod(m.c_str(), nullptr) - used;
    if (!avail || room < *avail) avail = std::max(room, 0.0);
  }
  return avail;
}

std::string format_bytes(double bytes) {
  const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB"};
  int u = 0;
  while (bytes >= 1024.0 && u < 5) {
    bytes /= 1024.0;
    ++u;
  }
  return u == 0 ? fmt::format("{:.0f} B", bytes) : fmt::format("{:.3g} {}", bytes, units[u]);
}

}  // namespace shatter::scene
