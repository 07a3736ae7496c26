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
  double worst = 0.0;
  for (std::size_t p = r.begin; p < r.end; ++p) {
    worst = std::max(worst, std::abs(pressure[p] - target[p - r.begin]) / p_ref);
    for (Field f : {Field::sxx, Field::syy, Field::szz}) P.col(f)[p] = -pressure[p];
    for (Field f : {Field::sxy, Field::syz, Field::sxz}) P.col(f)[p] = 0.0;
  }
  return worst;
}

double settle_group(ParticleStore& P, const MaterialModel& model, Range r, double G) {
  const BodySphere b = uniform_sphere(P, r);
  const double p0 = hydrostatic_pressure(G, b.rho, b.R, 0.0);
  if (!(p0 > 0.0)) return 0.0;
  const auto x = P.col(Field::x), y = P.col(Field::y), z = P.col(Field::z);
  std::vector<double> target(r.size());
  for (std::size_t p = r.begin; p < r.end; ++p) {
    const double d = std::hypot(x[p] - b.c[0], y[p] - b.c[1], z[p] - b.c[2]);
    target[p - r.begin] = hydrostatic_pressure(G, b.rho, b.R, d);
  }
  return settle(P, model, r, target, p0);
}

// The uniform-field column of one body (set_uniform_equilibrium); 0 for a body off the floor.
double settle_column(ParticleStore& P, const MaterialModel& model, Range r, double g_z, double z_lo,
                     double cell) {
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

double set_equilibrium(ParticleStore& P, const std::vector<MaterialPtr>& materials, double G) {
  require_stress(P);
  double worst = 0.0;
  for (const Group& g : P.groups()) {
    const MaterialModel& model = *materials[static_cast<std::size_t>(g.material)];
    worst = std::max(worst, settle_group(P, model, g.range, G));
  }
  return worst;
}

double set_uniform_equilibrium(ParticleStore& P, const std::vector<MaterialPtr>& materials,
                               double g_z, double z_lo, double cell) {
  require_stress(P);
  double worst = 0.0;
  for (const Group& g : P.groups()) {
    const MaterialModel& model = *materials[static_cast<std::size_t>(g.material)];
    worst = std::max(worst, settle_column(P, model, g.range, g_z, z_lo, cell));
  }
  return worst;
}

}  // namespace shatter::gravity
