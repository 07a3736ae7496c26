#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "scene/parts.hpp"
#include "scene/ranges.hpp"

namespace shatter::scene {
namespace {

const std::vector<std::string> kShapes = {"linear", "ugimp", "bspline2"};
const std::vector<std::string> kTransfers = {"flip", "apic"};
const std::vector<std::string> kPlanes = {"none", "x", "y", "z"};
const std::vector<std::string> kBoundaries = {"none", "fixed", "slip", "symmetry", "outflow"};
const std::vector<std::string> kFaces = {"x_lo", "x_hi", "y_lo", "y_hi", "z_lo", "z_hi"};

BoundaryKind boundary_of(const std::string& s) {
  if (s == "fixed") return BoundaryKind::fixed;
  if (s == "slip") return BoundaryKind::slip;
  if (s == "symmetry") return BoundaryKind::symmetry;
  if (s == "outflow") return BoundaryKind::outflow;
  return BoundaryKind::none;
}

}  // namespace

void read_solver(Reader& root, Scene& scene) {
  toml::table* t = root.subtable("solver");
  if (t == nullptr) root.fail("solver", "is required but missing (cell_size, end_time, ...)");
  Reader r(*t, "solver");
  r.allow({"shape", "transfer", "cell_size", "cfl", "end_time", "dt_max", "dt_min", "gravity",
           "symmetry_plane", "reorder_interval", "viscosity", "dt_floor_ratio"});
  r.reject_unknown();

  SolverConfig& c = scene.solver;
  const std::string shape = r.choice("shape", "ugimp", kShapes);
  c.shape = shape == "linear"  ? ShapeKind::linear
            : shape == "ugimp" ? ShapeKind::ugimp
                               : ShapeKind::bspline2;
  // flip: the paper's MUSL step; apic: affine PIC (see TransferKind in engine/config.hpp).
  const std::string transfer = r.choice("transfer", "flip", kTransfers);
  c.transfer = transfer == "flip" ? TransferKind::flip : TransferKind::apic;
  c.cell_size = r.positive("cell_size", r.number("cell_size"));
  r.within("cell_size", c.cell_size, ranges::kMinLength, ranges::kMaxLength, "m",
           ranges::kLengthReason);
  c.cfl = r.number("cfl", 0.3);
  // Eq. 34 is stable up to CFL = 1.
  if (!(c.cfl > 0.0 && c.cfl <= 1.0))
    r.fail("cfl", fmt::format("must be in (0, 1] (got {})", c.cfl));
  scene.end_time = r.positive("end_time", r.number("end_time"));
  r.within("end_time", scene.end_time, 0.0, ranges::kMaxTime, "s", ranges::kTimeReason);
  if (auto v = r.optional_number("dt_max")) c.dt_max = r.positive("dt_max", *v);
  c.dt_min = r.non_negative("dt_min", r.number("dt_min", 0.0));
  if (c.dt_min > 0.0 && c.dt_min >= c.dt_max) r.fail("dt_min", "must be smaller than dt_max");
  // Progress guard (docs/reliability.md). The stability scenes' smallest steps are 0.22 to 0.97
  // of the first (docs/stability.md), so 1e-4 stops only a collapse.
  scene.dt_floor_ratio = r.number("dt_floor_ratio", 1e-4);
  if (!(scene.dt_floor_ratio >= 0.0 && scene.dt_floor_ratio < 1.0)) {
    r.fail("dt_floor_ratio",
           fmt::format("must be in [0, 1) (got {}; 0 disables the check)", scene.dt_floor_ratio));
  }
  c.gravity = r.vec3("gravity", Vec3::Zero());
  r.within("gravity", c.gravity.norm(), 0.0, ranges::kMaxGravity, "m/s^2 (magnitude)",
           ranges::kGravityReason);
  const std::string plane = r.choice("symmetry_plane", "none", kPlanes);
  scene.symmetry_axis = plane == "none" ? -1 : plane[0] - 'x';
  const auto reorder = r.integer("reorder_interval", 25);
  if (reorder < 0) r.fail("reorder_interval", "must be >= 0");
  c.reorder_interval = static_cast<unsigned>(reorder);

  toml::table* v = r.subtable("viscosity");
  if (v == nullptr) {
    r.table().insert("viscosity", toml::table{});
    v = r.subtable("viscosity");
  }
  Reader q(*v, "solver.viscosity", r.where("viscosity"));
  q.allow({"linear", "quadratic"});
  q.reject_unknown();
  // Defaults are the common hydrocode choice (LS-DYNA's Q2 = 0.06 and Q1^2 = 1.5^2).
  c.viscosity.linear = q.non_negative("linear", q.number("linear", 0.06));
  c.viscosity.quadratic = q.non_negative("quadratic", q.number("quadratic", 2.25));
}

void read_domain(Reader& root, Scene& scene) {
  Domain& d = scene.solver.domain;
  const double h = scene.solver.cell_size;
  const int sym = scene.symmetry_axis;
  toml::table* t = root.subtable("domain");
  if (t == nullptr) {
    root.table().insert("domain", toml::table{});
    t = root.subtable("domain");
  }
  Reader r(*t, "domain", root.where("domain"));
  std::vector<std::string> allowed = {"lo", "hi", "boundary"};
  allowed.insert(allowed.end(), kFaces.begin(), kFaces.end());
  r.allow(allowed);
  r.reject_unknown();

  if (r.has("lo") != r.has("hi")) r.fail(r.has("lo") ? "hi" : "lo", "give both lo and hi");
  if (r.has("lo")) {
    // Faces must lie on grid planes; snap outward so a cell-size sweep needs no domain edits.
    for (const char* k : {"lo", "hi"}) {
      r.within(k, r.vec3(k).cwiseAbs().maxCoeff(), 0.0, ranges::kMaxCoordinate, "m (|coordinate|)",
               ranges::kCoordinateReason);
    }
    d.lo = (r.vec3("lo") / h).array().floor().matrix() * h;
    d.hi = (r.vec3("hi") / h).array().ceil().matrix() * h;
    for (int a = 0; a < 3; ++a) {
      if (!(d.lo[a] < d.hi[a]))
        r.fail("hi", fmt::format("must exceed lo on every axis (axis {})", a));
    }
  }
  if (sym >= 0) {
    if (r.has("lo") && d.lo[sym] != 0.0) {
      r.fail("lo", fmt::format("must be 0 on the {} axis: the symmetry plane (solver."
                               "symmetry_plane) is the lower face of the domain",
                               "xyz"[sym]));
    }
    d.lo[sym] = 0.0;
  }

  const std::string all = r.choice("boundary", "none", kBoundaries);
  if (all == "symmetry") r.fail("boundary", "set solver.symmetry_plane for a symmetry plane");
  for (int f = 0; f < 6; ++f) {
    const std::string& face = kFaces[static_cast<std::size_t>(f)];
    const bool is_symmetry_face = sym >= 0 && f == 2 * sym;
    std::string kind = all;
    if (r.has(face)) {
      kind = r.choice(face, all, kBoundaries);
      if (kind == "symmetry" && !is_symmetry_face) {
        r.fail(face, "a symmetry face must be the lower face of solver.symmetry_plane's axis");
      }
      if (is_symmetry_face && kind != "symmetry") {
        r.fail(face, "is the symmetry plane (solver.symmetry_plane) and cannot be " + kind);
      }
    }
    if (is_symmetry_face) kind = "symmetry";
    const double bound = (f % 2 == 0) ? d.lo[f / 2] : d.hi[f / 2];
    if (kind != "none" && !std::isfinite(bound)) {
      r.fail(r.has(face) ? face : "boundary",
             fmt::format("a '{}' boundary on face {} needs domain lo and hi", kind, face));
    }
    d.faces[static_cast<std::size_t>(f)] = boundary_of(kind);
  }
}

}  // namespace shatter::scene
