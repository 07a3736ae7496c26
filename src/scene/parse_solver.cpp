#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "scene/parts.hpp"
#include "scene/ranges.hpp"

namespace shatter::scene {
namespace {

const std::vector<std::string> kMethods = {"mpm", "sph"};
const std::vector<std::string> kShapes = {"linear", "ugimp", "bspline2"};
const std::vector<std::string> kTransfers = {"flip", "apic", "xpic", "fmpm"};
const std::vector<std::string> kPlanes = {"none", "x", "y", "z"};
const std::vector<std::string> kBoundaries = {"none", "fixed", "slip", "symmetry", "outflow"};
const std::vector<std::string> kContacts = {"single_field", "multi_field"};
const std::vector<std::string> kSphContinuity = {"standard", "normalized"};
const std::vector<std::string> kSphSwitches = {"none", "morris_monaghan"};
const std::vector<std::string> kFaces = {"x_lo", "x_hi", "y_lo", "y_hi", "z_lo", "z_hi"};
const std::vector<std::string> kGeometries = {"3d", "axisymmetric"};

BoundaryKind boundary_of(const std::string& s) {
  if (s == "fixed") return BoundaryKind::fixed;
  if (s == "slip") return BoundaryKind::slip;
  if (s == "symmetry") return BoundaryKind::symmetry;
  if (s == "outflow") return BoundaryKind::outflow;
  return BoundaryKind::none;
}

// solver.shape and solver.transfer, and the pairing the transfer needs from the shape.
void read_shape_and_transfer(Reader& r, SolverConfig& c) {
  const std::string shape = r.choice("shape", "ugimp", kShapes);
  c.shape = shape == "linear"  ? ShapeKind::linear
            : shape == "ugimp" ? ShapeKind::ugimp
                               : ShapeKind::bspline2;
  // flip: the paper's MUSL step; apic: affine PIC (see TransferKind in shatter/core/config.hpp).
  const std::string transfer = r.choice("transfer", "flip", kTransfers);
  c.transfer = transfer == "flip"   ? TransferKind::flip
               : transfer == "apic" ? TransferKind::apic
               : transfer == "xpic" ? TransferKind::xpic
                                    : TransferKind::fmpm;
  if (c.transfer == TransferKind::apic && c.shape == ShapeKind::linear) {
    // C_p = sum v_I grad N_I^T jumps when a point crosses a cell face with linear shapes; the
    // colliding-sphere test diverges within 50 steps. Jiang et al. (2015) use smooth kernels.
    r.fail("transfer",
           "\"apic\" needs a smooth shape function (solver.shape = \"ugimp\" or "
           "\"bspline2\"), not \"linear\"");
  }
}

// An order key of a filtering transfer (xpic_order, fmpm_order): an integer in [1, 32], read
// when `applies` (the transfer is `transfer`), else refused when given. Orders past ~40 are
// unstable (Hammerquist & Nairn 2017; each order is one more grid-particle-grid pass) and the
// binomial weights C(m, k) lose precision; FMPM(k) makes the same passes, so the same bound
// (Nairn 2026, arXiv 2604.07307, finds high orders need smaller time steps: large k is for
// study, not production).
void read_order(Reader& r, const char* key, bool applies, const char* transfer, int& order) {
  if (!applies) {
    if (r.has(key))
      r.fail(key, fmt::format("applies only with solver.transfer = \"{}\"", transfer));
    return;
  }
  const auto v = r.integer(key, order);
  if (v < 1 || v > 32) r.fail(key, fmt::format("must be an integer in [1, 32] (got {})", v));
  order = static_cast<int>(v);
}

// The options of one transfer scheme (pic_fraction, xpic_order, fmpm_order, filter_every,
// filter_heat): each refused under a transfer it does not apply to.
void read_transfer_options(Reader& r, SolverConfig& c) {
  // FLIP/PIC blend fraction (flip only) and XPIC order (xpic only); TransferKind says what each
  // does. The blend is read only when given, so scenes without it resolve as before.
  r.note_range("pic_fraction", "[0, 1]; flip only; absent = 0 (pure FLIP)");
  r.note_range("xpic_order", "[1, 32]; xpic only");
  if (auto f = r.optional_number("pic_fraction")) {
    if (c.transfer != TransferKind::flip)
      r.fail("pic_fraction", "applies only with solver.transfer = \"flip\"");
    if (!(*f >= 0.0 && *f <= 1.0))
      r.fail("pic_fraction", fmt::format("must be in [0, 1] (got {})", *f));
    c.pic_fraction = *f;
  }
  read_order(r, "xpic_order", c.transfer == TransferKind::xpic, "xpic", c.xpic_order);
  // FMPM order (fmpm only) and the periodic filter (xpic and fmpm: the filtered update on every
  // N-th step, FLIP on the others).
  r.note_range("fmpm_order", "[1, 32]; fmpm only");
  read_order(r, "fmpm_order", c.transfer == TransferKind::fmpm, "fmpm", c.fmpm_order);
  r.note_range("filter_every", "integer >= 1 (steps); xpic and fmpm only; absent = 1");
  if (r.has("filter_every")) {
    // APIC's C_p and the blend's fraction act on every step; a FLIP step would drop C_p.
    if (c.transfer != TransferKind::xpic && c.transfer != TransferKind::fmpm)
      r.fail("filter_every", "applies only with solver.transfer = \"xpic\" or \"fmpm\"");
    const auto every = r.integer("filter_every", 1);
    if (every < 1 || every > std::numeric_limits<int>::max())
      r.fail("filter_every", fmt::format("must be an integer >= 1 (got {})", every));
    c.filter_every = static_cast<int>(every);
  }
  // The filter-heat booking (read only when given, so scenes without it resolve as before).
  r.note_range("filter_heat", "xpic, fmpm, or flip with pic_fraction > 0; absent = false");
  if (r.has("filter_heat")) {
    c.filter_heat = r.boolean("filter_heat", false);
    const bool filters = c.transfer == TransferKind::xpic || c.transfer == TransferKind::fmpm ||
                         (c.transfer == TransferKind::flip && c.pic_fraction > 0.0);
    if (c.filter_heat && !filters)
      r.fail("filter_heat",
             "applies only with a filtering transfer: solver.transfer = \"xpic\" or \"fmpm\", or "
             "\"flip\" with pic_fraction > 0 (plain FLIP removes no kinetic energy; APIC's affine "
             "velocity keeps part of what its update drops)");
  }
}

// Grid spacing, time-step control and the end time, gravity, the symmetry plane, re-ordering.
void read_step_control(Reader& r, Scene& scene) {
  SolverConfig& c = scene.solver;
  c.cell_size = r.positive("cell_size", r.number("cell_size"));
  r.within("cell_size", c.cell_size, ranges::kMinLength, ranges::kMaxLength, "m",
           ranges::kLengthReason);
  c.cfl = r.number("cfl", 0.3);
  r.note_range("cfl", "(0, 1]");
  // Eq. 34 is stable up to CFL = 1.
  if (!(c.cfl > 0.0 && c.cfl <= 1.0))
    r.fail("cfl", fmt::format("must be in (0, 1] (got {})", c.cfl));
  scene.end_time = r.positive("end_time", r.number("end_time"));
  r.within("end_time", scene.end_time, 0.0, ranges::kMaxTime, "s", ranges::kTimeReason);
  r.note_range("dt_max", "", "s");
  r.note_range("dt_min", "< dt_max", "s");
  if (auto v = r.optional_number("dt_max")) c.dt_max = r.positive("dt_max", *v);
  c.dt_min = r.non_negative("dt_min", r.number("dt_min", 0.0));
  if (c.dt_min > 0.0 && c.dt_min >= c.dt_max) r.fail("dt_min", "must be smaller than dt_max");
  // Progress guard (docs/reliability.md). The stability scenes' smallest steps are 0.22 to 0.97
  // of the first (docs/stability.md), so 1e-4 stops only a collapse.
  scene.dt_floor_ratio = r.number("dt_floor_ratio", 1e-4);
  r.note_range("dt_floor_ratio", "[0, 1); 0 disables");
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
  r.note_range("reorder_interval", ">= 0", "steps");
  if (reorder < 0) r.fail("reorder_interval", "must be >= 0");
  c.reorder_interval = static_cast<unsigned>(reorder);
}

// solver.method and [solver.sph] (read when given, or with method = "sph").
void read_method_and_sph(Reader& r, Scene& scene) {
  // The method (issue 10): MPM (default; not written back, so MPM scenes resolve as before) or
  // Benz & Asphaug's SPH (include/shatter/sph/solver.hpp).
  if (r.has("method")) scene.method = r.choice("method", "mpm", kMethods);
  toml::table* sph = r.subtable("sph");
  if (sph != nullptr || scene.method == "sph") {
    toml::table& t = table_or_empty(r, "sph");
    Reader q(t, "solver.sph", r.where("sph"));
    q.allow({"h_factor", "alpha", "beta", "skin", "continuity", "viscosity_switch", "alpha_min",
             "alpha_max", "switch_decay"});
    q.reject_unknown();
    scene.sph.h_factor = q.positive("h_factor", q.number("h_factor", scene.sph.h_factor));
    scene.sph.alpha = q.non_negative("alpha", q.number("alpha", scene.sph.alpha));
    scene.sph.beta = q.non_negative("beta", q.number("beta", scene.sph.beta));
    scene.sph.skin = q.non_negative("skin", q.number("skin", scene.sph.skin));
    // Both default to today's formulation (BA95 Eq. 16, constant Monaghan viscosity), so
    // scenes without them run bit for bit as before (include/shatter/sph/config.hpp).
    scene.sph.continuity = q.choice("continuity", "standard", kSphContinuity) == "normalized"
                               ? sph::Continuity::normalized
                               : sph::Continuity::standard;
    scene.sph.viscosity_switch =
        q.choice("viscosity_switch", "none", kSphSwitches) == "morris_monaghan"
            ? sph::ViscositySwitch::morris_monaghan
            : sph::ViscositySwitch::none;
    scene.sph.alpha_min = q.non_negative("alpha_min", q.number("alpha_min", scene.sph.alpha_min));
    scene.sph.alpha_max = q.non_negative("alpha_max", q.number("alpha_max", scene.sph.alpha_max));
    scene.sph.switch_decay =
        q.positive("switch_decay", q.number("switch_decay", scene.sph.switch_decay));
    if (scene.sph.alpha_min > scene.sph.alpha_max) {
      q.fail("alpha_min", fmt::format("must not exceed alpha_max (got {} > {})",
                                      scene.sph.alpha_min, scene.sph.alpha_max));
    }
  }
}

// [[solver.contact_pair]]: per-pair Coulomb coefficients, resolved to body ids once the bodies are
// read (resolve_contact_pairs).
void read_contact_pairs(Reader& r, Scene& scene) {
  r.note_type("contact_pair", "array of tables");
  if (toml::node* pairs = r.table().get("contact_pair")) {
    toml::array* a = pairs->as_array();
    if (a == nullptr) {
      r.fail("contact_pair",
             "must be an array of tables ([[solver.contact_pair]] with bodies and friction)");
    }
    for (std::size_t k = 0; k < a->size(); ++k) {
      toml::table* pt = (*a)[k].as_table();
      const std::string path = fmt::format("solver.contact_pair[{}]", k);
      if (pt == nullptr) r.fail("contact_pair", fmt::format("element {} is not a table", k));
      Reader q(*pt, path, r.where("contact_pair"));
      q.allow({"bodies", "friction"});
      q.reject_unknown();
      ContactPairSpec spec;
      spec.where = q.where("bodies");
      spec.key = q.key_path("bodies");
      q.note_type("bodies", "[\"body\", \"body\"]");
      q.note_default("bodies", "*required*");
      const toml::node* names = q.table().get("bodies");
      const toml::array* na = names ? names->as_array() : nullptr;
      if (na == nullptr || na->size() != 2 || !(*na)[0].is_string() || !(*na)[1].is_string()) {
        q.fail("bodies", "must be an array of two body names, e.g. [\"projectile\", \"target\"]");
      }
      spec.a = (*na)[0].as_string()->get();
      spec.b = (*na)[1].as_string()->get();
      if (spec.a == spec.b) q.fail("bodies", "must name two different bodies");
      spec.friction = q.non_negative("friction", q.number("friction"));
      scene.contact_pairs.push_back(spec);
    }
  }
}

// solver.contact, with friction and the contact pairs for multi-field contact.
void read_contact(Reader& r, Scene& scene) {
  SolverConfig& c = scene.solver;
  // Contact between bodies (engine/config.hpp ContactKind). The paper's single shared field is
  // the default: it is what the paper ran, and it keeps earlier results bitwise.
  const std::string contact = r.choice("contact", "single_field", kContacts);
  c.contact.kind = contact == "multi_field" ? ContactKind::multi_field : ContactKind::single_field;
  if (c.contact.kind == ContactKind::multi_field && scene.method == "sph") {
    r.fail("contact",
           "applies only with solver.method = \"mpm\" (SPH bodies meet through their "
           "particles' pair forces)");
  }
  if (c.contact.kind == ContactKind::single_field) {
    for (const char* key : {"friction", "contact_pair"}) {
      if (r.has(key)) r.fail(key, "applies only with solver.contact = \"multi_field\"");
    }
  } else {
    // Coulomb coefficient of every pair of bodies not listed in contact_pair.
    c.contact.friction = r.non_negative("friction", r.number("friction", 0.0));
    read_contact_pairs(r, scene);
  }
}

// [solver.mpi]: the load balancing of a run on several MPI ranks (MpiTuning, docs/mpi.md), MPM
// only; written into the run's scene copy so that a run records the values it ran with.
void read_mpi(Reader& r, Scene& scene) {
  if (scene.method != "mpm") {
    if (r.has("mpi"))
      r.fail("mpi", "applies only with solver.method = \"mpm\" (SPH runs on one rank)");
    return;
  }
  MpiTuning& m = scene.solver.mpi;
  toml::table& t = table_or_empty(r, "mpi");
  Reader q(t, "solver.mpi", r.where("mpi"));
  q.allow({"rebalance_every", "imbalance"});
  q.reject_unknown();
  const auto every = q.integer("rebalance_every", m.rebalance_every);
  q.note_range("rebalance_every", ">= 1", "steps");
  if (every < 1 || every > std::numeric_limits<int>::max())
    q.fail("rebalance_every", fmt::format("must be an integer >= 1 (got {})", every));
  m.rebalance_every = static_cast<unsigned>(every);
  m.imbalance = q.number("imbalance", m.imbalance);
  // max/mean is >= 1 on any cut: 1 recuts at every check (the MPI tests' setting).
  q.note_range("imbalance", ">= 1 (largest / mean particles per rank); 1 = recut at every check");
  if (!(m.imbalance >= 1.0 && std::isfinite(m.imbalance)))
    q.fail("imbalance", fmt::format("must be a number >= 1 (got {})", m.imbalance));
}

// solver.geometry (issue 31): "3d" (default; not written back, so 3-D scenes resolve as before)
// or "axisymmetric", the MPM engine in (r, z) = (x, z) (SolverConfig::Geometry). The r-z mode
// takes the axis r = 0 as the symmetry face x_lo; what it does not carry yet is refused here,
// by the key that asks for it (docs/validation-axisymmetric.md, "What is refused").
void read_geometry(Reader& r, Scene& scene) {
  if (!r.has("geometry") || r.choice("geometry", "3d", kGeometries) == "3d") return;
  SolverConfig& c = scene.solver;
  c.geometry = Geometry::axisymmetric;
  if (scene.method == "sph") {
    r.fail("method",
           "\"sph\" has no r-z form yet: solver.geometry = \"axisymmetric\" runs "
           "with solver.method = \"mpm\"");
  }
  if (c.shape == ShapeKind::ugimp) {
    // Nairn & Guilkey (2015, IJNME 101): uGIMP in r-z needs shape functions integrated with the
    // radial weight over the particle domain, which the 3-D uGIMP is not.
    r.fail("shape",
           "\"axisymmetric\" needs solver.shape = \"linear\" or \"bspline2\" (uGIMP in r-z "
           "needs the r-weighted shapes of Nairn & Guilkey 2015, not implemented)");
  }
  if (c.transfer != TransferKind::flip) {
    r.fail("transfer",
           "must be \"flip\" with solver.geometry = \"axisymmetric\" (APIC's affine "
           "momentum has no hoop term yet; the filters are not verified in r-z)");
  }
  if (c.contact.kind == ContactKind::multi_field) {
    r.fail("contact",
           "\"multi_field\" is not supported with solver.geometry = \"axisymmetric\" "
           "yet (its contact normals use 3-D stencils)");
  }
  if (scene.symmetry_axis >= 0) {
    r.fail("symmetry_plane",
           "does not apply with solver.geometry = \"axisymmetric\": the axis "
           "r = 0 is the symmetry face of the r-z mode");
  }
  if (c.gravity.x() != 0.0 || c.gravity.y() != 0.0) {
    r.fail("gravity", "must lie along z with solver.geometry = \"axisymmetric\"");
  }
  scene.symmetry_axis = 0;  // the axis: x_lo at x = 0 is a symmetry face (read_domain)
}

// [solver.viscosity]: the artificial bulk viscosity's coefficients.
void read_viscosity(Reader& r, SolverConfig& c) {
  toml::table& v = table_or_empty(r, "viscosity");
  Reader q(v, "solver.viscosity", r.where("viscosity"));
  q.allow({"linear", "quadratic"});
  q.reject_unknown();
  // Defaults are the common hydrocode choice (LS-DYNA's Q2 = 0.06 and Q1^2 = 1.5^2).
  c.viscosity.linear = q.non_negative("linear", q.number("linear", 0.06));
  c.viscosity.quadratic = q.non_negative("quadratic", q.number("quadratic", 2.25));
}

}  // namespace

void read_solver(Reader& root, Scene& scene) {
  root.note_default("solver", "*required*");
  toml::table* t = root.subtable("solver");
  if (t == nullptr) root.fail("solver", "is required but missing (cell_size, end_time, ...)");
  Reader r(*t, "solver");
  r.allow({"method",           "shape",          "transfer",     "cell_size",  "cfl",
           "end_time",         "dt_max",         "dt_min",       "gravity",    "symmetry_plane",
           "reorder_interval", "viscosity",      "sph",          "contact",    "friction",
           "contact_pair",     "dt_floor_ratio", "pic_fraction", "xpic_order", "fmpm_order",
           "filter_every",     "filter_heat",    "mpi",          "geometry"});
  r.reject_unknown();

  read_shape_and_transfer(r, scene.solver);
  read_transfer_options(r, scene.solver);
  read_step_control(r, scene);
  read_method_and_sph(r, scene);
  read_contact(r, scene);
  read_viscosity(r, scene.solver);
  read_mpi(r, scene);
  read_geometry(r, scene);
}

void read_domain(Reader& root, Scene& scene) {
  Domain& d = scene.solver.domain;
  const double h = scene.solver.cell_size;
  const int sym = scene.symmetry_axis;
  toml::table& t = table_or_empty(root, "domain");
  Reader r(t, "domain", root.where("domain"));
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

  const bool rz = scene.solver.geometry == Geometry::axisymmetric;
  if (rz) {
    // The r-z plane is y = 0: the domain is one layer of nodes thick in y and has no y faces.
    for (const char* face : {"y_lo", "y_hi"}) {
      if (r.has(face)) {
        r.fail(face, "does not apply with solver.geometry = \"axisymmetric\" (no y faces)");
      }
    }
    d.lo.y() = -h;
    d.hi.y() = h;
  }
  const std::string all = r.choice("boundary", "none", kBoundaries);
  if (all == "symmetry") r.fail("boundary", "set solver.symmetry_plane for a symmetry plane");
  for (int f = 0; f < 6; ++f) {
    const std::string& face = kFaces[static_cast<std::size_t>(f)];
    const bool is_symmetry_face = sym >= 0 && f == 2 * sym;
    std::string kind = all;
    r.note_default(face, "the value of `boundary`");
    if (r.has(face)) {
      kind = r.choice(face, all, kBoundaries);
      if (kind == "symmetry" && !is_symmetry_face) {
        r.fail(face, "a symmetry face must be the lower face of solver.symmetry_plane's axis");
      }
      if (is_symmetry_face && kind != "symmetry") {
        r.fail(face, (rz ? "is the axis r = 0 (solver.geometry = \"axisymmetric\")"
                         : "is the symmetry plane (solver.symmetry_plane)") +
                         std::string(" and cannot be ") + kind);
      }
    }
    if (is_symmetry_face) kind = "symmetry";
    if (rz && f / 2 == 1) kind = "none";
    const double bound = (f % 2 == 0) ? d.lo[f / 2] : d.hi[f / 2];
    if (kind != "none" && !std::isfinite(bound)) {
      r.fail(r.has(face) ? face : "boundary",
             fmt::format("a '{}' boundary on face {} needs domain lo and hi", kind, face));
    }
    d.faces[static_cast<std::size_t>(f)] = boundary_of(kind);
  }
}

void resolve_contact_pairs(Scene& scene) {
  for (const ContactPairSpec& p : scene.contact_pairs) {
    std::int64_t ids[2] = {-1, -1};
    const std::string* names[2] = {&p.a, &p.b};
    for (int k = 0; k < 2; ++k) {
      for (std::size_t g = 0; g < scene.bodies.size(); ++g) {
        if (scene.bodies[g].name == *names[k]) ids[k] = static_cast<std::int64_t>(g);
      }
      if (ids[k] < 0)
        throw SceneError(p.where, p.key, fmt::format("no body named '{}'", *names[k]));
    }
    // Body ids are the order of scene.bodies (scene/build.cpp sets IField::body = group).
    scene.solver.contact.pairs.push_back({ids[0], ids[1], p.friction});
  }
}

}  // namespace shatter::scene
