// The lithostatic start (see shatter/gravity/equilibrium.hpp).

#include "shatter/gravity/equilibrium.hpp"

#include <algorithm>
#include <cmath>

namespace shatter::gravity {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Secant steps from rho c_p^2: c_p is the longitudinal speed, so rho c_p^2 = K + 4/3 mu
// overestimates the bulk modulus by (1 + 4 mu / 3 K) ~ 2 for rock, and each step closes about
// half the residual; 30 steps leave < 1e-8 of it.
constexpr int kSteps = 30;

struct BodySphere {
  double rho = 0.0, R = 0.0;
  double c[3] = {0.0, 0.0, 0.0};
};

BodySphere uniform_sphere(const ParticleStore& P, Range r) {
  const auto m = P.col(Field::mass), v = P.col(Field::volume0);
  const auto x = P.col(Field::x), y = P.col(Field::y), z = P.col(Field::z);
  double M = 0.0, V = 0.0, mx = 0.0, my = 0.0, mz = 0.0;
  for (std::size_t p = r.begin; p < r.end; ++p) {
    M += m[p], V += v[p];
    mx += m[p] * x[p], my += m[p] * y[p], mz += m[p] * z[p];
  }
  BodySphere b;
  if (!(M > 0.0 && V > 0.0)) return b;
  b.rho = M / V;
  b.R = std::cbrt(3.0 * V / (4.0 * kPi));
  b.c[0] = mx / M, b.c[1] = my / M, b.c[2] = mz / M;
  return b;
}

// Stress -p I from each point's EOS pressure (the model's initialise has run); returns the largest
// |p - target| / p_ref.
double stress_from_pressure(ParticleStore& P, Range r, const std::vector<double>& target,
                            double p_ref) {
  const auto pressure = P.col(Field::pressure);
  double worst = 0.0;
  for (std::size_t p = r.begin; p < r.end; ++p) {
    worst = std::max(worst, std::abs(pressure[p] - target[p - r.begin]) / p_ref);
    for (Field f : {Field::sxx, Field::syy, Field::szz}) P.col(f)[p] = -pressure[p];
    for (Field f : {Field::sxy, Field::syz, Field::sxz}) P.col(f)[p] = 0.0;
  }
  return worst;
}

// Density raised until the EOS gives each point's target pressure; stress -p I. Returns the
// largest |p - target| / p_ref.
double settle(ParticleStore& P, const MaterialModel& model, Range r,
              const std::vector<double>& target, double p_ref) {
  auto rho = P.col(Field::rho);
  const auto pressure = P.col(Field::pressure), c = P.col(Field::soundspeed);
  model.initialise(P, r);
  for (int step = 0; step < kSteps; ++step) {
    for (std::size_t p = r.begin; p < r.end; ++p) {
      const double K = rho[p] * c[p] * c[p];
      if (K > 0.0) rho[p] += rho[p] * (target[p - r.begin] - pressure[p]) / K;
    }
    model.initialise(P, r);
  }
  return stress_from_pressure(P, r, target, p_ref);
}

// Whether a body starts on its crush curve (issue 29): its material's compaction at rest gives a
// distension above 1 at the reference density. A dense material, and a porous one given porosity
// 0, start as before.
bool starts_porous(const RestCompactionFn& rest, const MaterialModel& model, double e) {
  return rest && rest(model.reference_density(), e).alpha > 1.0;
}

// The bulk density at which a porous material at rest carries bulk pressure p (energy e): the
// root of q(rho) = p, q the pressure of its compaction model at rest (rest_compaction.hpp)
// (increasing in rho: the matrix density alpha rho grows along both crush curves), between lo
// (q(lo) <= p) and an upper end found by doubling the step from lo. Illinois false position (Dowell
// & Jarratt 1971, BIT 11), to a bracket of 1e-13 rho; at most 200 steps.
double rest_density(const RestCompactionFn& rest, double p, double e, double lo) {
  auto q = [&](double rho) { return rest(rho, e).pressure - p; };
  double f_lo = q(lo);
  if (f_lo >= 0.0) return lo;
  double step = 1e-3 * lo, hi = lo + step, f_hi = q(hi);
  for (int k = 0; k < 60 && f_hi < 0.0; ++k) {
    lo = hi, f_lo = f_hi, step *= 2.0;
    hi = lo + step, f_hi = q(hi);
  }
  int side = 0;
  for (int k = 0; k < 200 && hi - lo > 1e-13 * hi; ++k) {
    // every fourth step a bisection: the bracket shrinks even where round-off in q (P-alpha's
    // root is found to 1e-12 in alpha) misleads the secant
    double x = k % 4 == 3 ? 0.5 * (lo + hi) : (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
    if (!(x > lo && x < hi)) x = 0.5 * (lo + hi);
    const double f = q(x);
    if (f == 0.0) return x;
    if (f < 0.0) {
      lo = x, f_lo = f;
      if (side == -1) f_hi *= 0.5;
      side = -1;
    } else {
      hi = x, f_hi = f;
      if (side == 1) f_lo *= 0.5;
      side = 1;
    }
  }
  return 0.5 * (lo + hi);
}

// The lithostatic column of a porous body (issue 29): the overburden of a column whose bulk
// density grows with depth as its pores close, dp/dd = g rho(p) from p = 0 at the free surface
// (the differential form of p = rho g y, Turcotte & Schubert 2002 Eq. 2-1, with the density
// of the compacted bulk), rho(p) the density at which the compaction model at rest carries p
// (rest_compaction.hpp). Integrated by RK4 on kNodes equal steps in depth; each
// point then takes p at its depth (cubic Hermite between the nodes, dp/dd known there), the
// density that carries it, the crush curve's distension at that density, and the mass of its
// volume at that density: its volume (volume0, the space its lattice site tiles) is kept and its
// mass follows alpha, m = rho volume0, so the grid's density is the point's and the column is in
// balance without moving a point (an Eulerian code's lithostatic set-up keeps the cells' volume
// the same way). The body's mass grows by the compaction. Returns the largest |p - target| /
// p_max after the model's initialise.
double settle_porous_column(ParticleStore& P, const MaterialModel& model,
                            const RestCompactionFn& rest, Range r, double g_z, double top,
                            double bottom) {
  constexpr int kNodes = 1024;
  const double H = top - bottom, h = H / kNodes, rho_rest = model.reference_density();
  const double e0 = P.col(Field::energy)[r.begin];
  std::vector<double> pn(kNodes + 1), rn(kNodes + 1);
  pn[0] = 0.0, rn[0] = rest_density(rest, 0.0, e0, rho_rest);
  for (int k = 0; k < kNodes; ++k) {  // RK4 on dp/dd = g rho(p)
    const double p = pn[k], lo = rn[k];
    const double k1 = g_z * lo;
    const double k2 = g_z * rest_density(rest, p + 0.5 * h * k1, e0, lo);
    const double k3 = g_z * rest_density(rest, p + 0.5 * h * k2, e0, lo);
    const double k4 = g_z * rest_density(rest, p + h * k3, e0, lo);
    pn[k + 1] = p + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    rn[k + 1] = rest_density(rest, pn[k + 1], e0, lo);
  }
  auto rho = P.col(Field::rho), alpha = P.col(Field::distension), m = P.col(Field::mass);
  const auto z = P.col(Field::z), v = P.col(Field::volume0), e = P.col(Field::energy);
  std::vector<double> target(r.size());
  for (std::size_t p = r.begin; p < r.end; ++p) {
    const double d = std::clamp(top - z[p], 0.0, H);
    const int k = std::min(static_cast<int>(d / h), kNodes - 1);
    const double t = d / h - k, t2 = t * t, t3 = t2 * t;  // cubic Hermite on [d_k, d_k+1]
    const double pt = (2 * t3 - 3 * t2 + 1) * pn[k] + (t3 - 2 * t2 + t) * h * g_z * rn[k] +
                      (-2 * t3 + 3 * t2) * pn[k + 1] + (t3 - t2) * h * g_z * rn[k + 1];
    rho[p] = rest_density(rest, pt, e[p], rn[k]);
    alpha[p] = rest(rho[p], e[p]).alpha;
    m[p] = rho[p] * v[p];
    target[p - r.begin] = pt;
  }
  model.initialise(P, r);
  return stress_from_pressure(P, r, target, pn[kNodes]);
}

// The radial profile of a self-gravitating porous sphere (issue 29): p, bulk density rho and
// enclosed mass m at r_k = k h, k = 0 .. kShells, h = R / kShells. The central pressure converges
// at second order in h (likely the rest density's kinks, such as a crush curve's elastic limit,
// not smooth for RK4): 128 / 256 / 512 / 1 024 shells give p(0) of the 500 km regolith_simulant
// sphere (scenes/gravity/porous-sphere.toml) 1.5e-6 / 3.7e-7 / 9e-8 / 2e-8 above its Richardson
// limit.
constexpr int kShells = 256;
struct SphereProfile {
  double h = 0.0;
  std::vector<double> p, rho, m;
};

// dp/dr of a spherical body in hydrostatic balance, -G m rho / r^2, m the mass inside r (the
// stellar-structure equations' first two, as written e.g. in the GYRE reference guide,
// "Equilibrium state": dP/dr = -rho G M_r / r^2, M_r = int 4 pi rho r^2 dr); 0 at the centre.
double pressure_slope(double G, double r, double m, double rho) {
  return r > 0.0 ? -G * m * rho / (r * r) : 0.0;
}

// One shot of the profile from central pressure pc: RK4 outward on y = (p, m), dp/dr as above and
// dm/dr = 4 pi r^2 rho(p), rho(p) the density at which the compaction model at rest carries p
// (rest_density from rho_lo, the density at p = 0). The first shell from the centre's series,
// m = 4/3 pi rho_c r^3, p = pc - 2/3 pi G rho_c^2 r^2 (a uniform core: the density's own slope
// there enters at r^4), so that no step divides by the centre's r = 0. Returns p(R).
double shoot_sphere(const RestCompactionFn& rest, double e0, double rho_lo, double G, double pc,
                    SphereProfile& s) {
  const double h = s.h;
  const auto rho_at = [&](double p) { return rest_density(rest, p, e0, rho_lo); };
  s.p.assign(kShells + 1, 0.0), s.rho.assign(kShells + 1, 0.0), s.m.assign(kShells + 1, 0.0);
  s.p[0] = pc, s.rho[0] = rho_at(pc);
  s.m[1] = 4.0 / 3.0 * kPi * s.rho[0] * h * h * h;
  s.p[1] = pc - 2.0 / 3.0 * kPi * G * s.rho[0] * s.rho[0] * h * h;
  s.rho[1] = rho_at(s.p[1]);
  for (int k = 1; k < kShells; ++k) {
    const double r = k * h, p = s.p[k], m = s.m[k];
    const auto dm = [&](double x, double rho) { return 4.0 * kPi * x * x * rho; };
    const double r1 = s.rho[k], a1 = pressure_slope(G, r, m, r1), b1 = dm(r, r1);
    const double r2 = rho_at(p + 0.5 * h * a1);
    const double a2 = pressure_slope(G, r + 0.5 * h, m + 0.5 * h * b1, r2);
    const double b2 = dm(r + 0.5 * h, r2);
    const double r3 = rho_at(p + 0.5 * h * a2);
    const double a3 = pressure_slope(G, r + 0.5 * h, m + 0.5 * h * b2, r3);
    const double b3 = dm(r + 0.5 * h, r3);
    const double r4 = rho_at(p + h * a3);
    const double a4 = pressure_slope(G, r + h, m + h * b3, r4), b4 = dm(r + h, r4);
    s.p[k + 1] = p + h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4);
    s.m[k + 1] = m + h / 6.0 * (b1 + 2.0 * b2 + 2.0 * b3 + b4);
    s.rho[k + 1] = rho_at(s.p[k + 1]);
  }
  return s.p[kShells];
}

// The profile whose pressure vanishes at the surface, p(R) = 0: secant steps on pc from the
// uniform sphere's central pressure at the rest density (p(R) grows with pc nearly linearly: the
// density's own change with pc is second order), to |p(R)| < 1e-12 pc; at most 40 shots.
SphereProfile porous_sphere(const RestCompactionFn& rest, double e0, double rho_lo, double G,
                            double R) {
  SphereProfile s;
  s.h = R / kShells;
  double x0 = hydrostatic_pressure(G, rho_lo, R, 0.0), x1 = 1.02 * x0;
  double f0 = shoot_sphere(rest, e0, rho_lo, G, x0, s);
  for (int k = 0; k < 40; ++k) {
    const double f1 = shoot_sphere(rest, e0, rho_lo, G, x1, s);
    if (std::abs(f1) < 1e-12 * x1 || f1 == f0) break;
    double x2 = x1 - f1 * (x1 - x0) / (f1 - f0);
    if (!(x2 > 0.0)) x2 = 0.5 * x1;
    x0 = x1, f0 = f1, x1 = x2;
  }
  return s;
}

// The self-gravitating sphere of a porous body (issue 29): the body's uniform sphere (its centre
// of mass and the radius of its volume, as a dense body's) in hydrostatic equilibrium with a bulk
// density that grows inward as its pores close (porous_sphere), each point at its radius's
// pressure (cubic Hermite between the shells, dp/dr known there), the density that carries it at
// rest, the crush curve's distension there and the mass of its volume at that density,
// m = rho volume0, as the uniform-field column does (settle_porous_column): positions and volume0
// are kept, so the points still tile the sphere, and the mass the gravity solver sees is the
// profile's m(r); the body's mass grows by the compaction. Returns the largest |p - target| /
// p(0) after the model's initialise.
double settle_porous_sphere(ParticleStore& P, const MaterialModel& model,
                            const RestCompactionFn& rest, Range r, double G, const BodySphere& b) {
  const double e0 = P.col(Field::energy)[r.begin];
  const double rho_lo = rest_density(rest, 0.0, e0, model.reference_density());
  const SphereProfile s = porous_sphere(rest, e0, rho_lo, G, b.R);
  auto rho = P.col(Field::rho), alpha = P.col(Field::distension), m = P.col(Field::mass);
  const auto x = P.col(Field::x), y = P.col(Field::y), z = P.col(Field::z);
  const auto v = P.col(Field::volume0), e = P.col(Field::energy);
  std::vector<double> target(r.size());
  const auto slope = [&](int k) { return pressure_slope(G, k * s.h, s.m[k], s.rho[k]); };
  for (std::size_t p = r.begin; p < r.end; ++p) {
    const double d = std::min(std::hypot(x[p] - b.c[0], y[p] - b.c[1], z[p] - b.c[2]), b.R);
    const int k = std::min(static_cast<int>(d / s.h), kShells - 1);
    const double t = d / s.h - k, t2 = t * t, t3 = t2 * t;  // cubic Hermite on [r_k, r_k+1]
    const double pt = (2 * t3 - 3 * t2 + 1) * s.p[k] + (t3 - 2 * t2 + t) * s.h * slope(k) +
                      (-2 * t3 + 3 * t2) * s.p[k + 1] + (t3 - t2) * s.h * slope(k + 1);
    // the outer shell's density is a lower bound of the root where pt >= p_k+1: fewer steps
    rho[p] = rest_density(rest, pt, e[p], pt >= s.p[k + 1] ? s.rho[k + 1] : rho_lo);
    alpha[p] = rest(rho[p], e[p]).alpha;
    m[p] = rho[p] * v[p];
    target[p - r.begin] = pt;
  }
  model.initialise(P, r);
  return stress_from_pressure(P, r, target, s.p[0]);
}

// The self-gravity start of one body (set_equilibrium).
double settle_group(ParticleStore& P, const MaterialModel& model, const RestCompactionFn& rest,
                    Range r, double G) {
  const BodySphere b = uniform_sphere(P, r);
  const double p0 = hydrostatic_pressure(G, b.rho, b.R, 0.0);
  if (!(p0 > 0.0)) return 0.0;
  if (starts_porous(rest, model, P.col(Field::energy)[r.begin])) {
    return settle_porous_sphere(P, model, rest, r, G, b);
  }
  const auto x = P.col(Field::x), y = P.col(Field::y), z = P.col(Field::z);
  std::vector<double> target(r.size());
  for (std::size_t p = r.begin; p < r.end; ++p) {
    const double d = std::hypot(x[p] - b.c[0], y[p] - b.c[1], z[p] - b.c[2]);
    target[p - r.begin] = hydrostatic_pressure(G, b.rho, b.R, d);
  }
  return settle(P, model, r, target, p0);
}

// The uniform-field column of one body (set_uniform_equilibrium); 0 for a body off the floor.
double settle_column(ParticleStore& P, const MaterialModel& model, const RestCompactionFn& rest,
                     Range r, double g_z, double z_lo, double cell) {
  if (r.size() == 0) return 0.0;
  const auto m = P.col(Field::mass), v = P.col(Field::volume0);
  const auto z = P.col(Field::z), s = P.col(Field::size0);
  double M = 0.0, V = 0.0, bottom = z[r.begin], top = z[r.begin] + 0.5 * s[r.begin];
  for (std::size_t p = r.begin; p < r.end; ++p) {
    M += m[p], V += v[p];
    bottom = std::min(bottom, z[p]);
    top = std::max(top, z[p] + 0.5 * s[p]);
  }
  if (!(M > 0.0 && V > 0.0) || bottom - z_lo > cell) return 0.0;
  const double rho = M / V, p_max = lithostatic_pressure(rho, g_z, top - bottom);
  if (!(p_max > 0.0)) return 0.0;
  // A dense body's compression p / K ~ 1e-3 needs no mass change.
  if (starts_porous(rest, model, P.col(Field::energy)[r.begin])) {
    return settle_porous_column(P, model, rest, r, g_z, top, bottom);
  }
  std::vector<double> target(r.size());
  for (std::size_t p = r.begin; p < r.end; ++p) {
    target[p - r.begin] = lithostatic_pressure(rho, g_z, top - z[p]);
  }
  return settle(P, model, r, target, p_max);
}

void require_stress(ParticleStore& P) {
  P.require(FieldSet{Field::pressure, Field::soundspeed, Field::sxx, Field::syy, Field::szz,
                     Field::sxy, Field::syz, Field::sxz});
}

}  // namespace

double hydrostatic_pressure(double G, double rho, double R, double r) {
  return r < R ? 2.0 / 3.0 * kPi * G * rho * rho * (R * R - r * r) : 0.0;
}

double lithostatic_pressure(double rho, double g_z, double depth) {
  return depth > 0.0 ? rho * g_z * depth : 0.0;
}

double set_equilibrium(ParticleStore& P, const std::vector<MaterialPtr>& materials, double G,
                       const std::vector<RestCompactionFn>& rest) {
  require_stress(P);
  double worst = 0.0;
  for (const Group& g : P.groups()) {
    const auto k = static_cast<std::size_t>(g.material);
    const RestCompactionFn none;
    const RestCompactionFn& q = k < rest.size() ? rest[k] : none;
    worst = std::max(worst, settle_group(P, *materials[k], q, g.range, G));
  }
  return worst;
}

double set_uniform_equilibrium(ParticleStore& P, const std::vector<MaterialPtr>& materials,
                               double g_z, double z_lo, double cell,
                               const std::vector<RestCompactionFn>& rest) {
  require_stress(P);
  double worst = 0.0;
  for (const Group& g : P.groups()) {
    const auto k = static_cast<std::size_t>(g.material);
    const RestCompactionFn none;
    const RestCompactionFn& q = k < rest.size() ? rest[k] : none;
    worst = std::max(worst, settle_column(P, *materials[k], q, g.range, g_z, z_lo, cell));
  }
  return worst;
}

}  // namespace shatter::gravity
