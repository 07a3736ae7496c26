// The two selectable SPH formulations of issue 11 (include/shatter/sph/config.hpp): the
// normalized continuity (the fix of the rho < 0 stop of crater ejecta at low viscosity) and the
// Morris & Monaghan (1997) viscosity switch, first term by term against their analytic
// solutions, then in the solver.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "shatter/scene/build.hpp"
#include "shatter/scene/scene.hpp"
#include "shatter/sph/solver.hpp"
#include "sph/gather.hpp"
#include "sph/terms.hpp"
#include "support/sph_impact.hpp"

namespace shatter::sph {
namespace {

namespace ks = kernels::sph;

// One particle of a quarter of its neighbours' density inside a homologously expanding lattice,
// x = x0 (1 + e t), v = e x0 (div v = 3 e / (1 + e t)): the continuum keeps every density ratio,
// rho_i(t) = rho_i(0) / (1 + e t)^3. The neighbours follow that exactly (set each step); the
// centre's density is integrated by the rates pass.
struct Expansion {
  double et_nonpositive = -1.0;  // e t at which rho_i <= 0 (-1: never, to e t = 0.5)
  double ratio = 0.0;            // rho_i / continuum at e t = 0.5
};

Expansion expand(bool normalized) {
  constexpr int kHalf = 6, kN = 2 * kHalf + 1;
  constexpr double s0 = 1e-3, rho0 = 1000.0, e = 1e4, rho_i0 = 0.25 * rho0;
  const double m = rho0 * s0 * s0 * s0;
  std::vector<double> x0, y0, z0;
  for (int a = -kHalf; a <= kHalf; ++a) {
    for (int b = -kHalf; b <= kHalf; ++b) {
      for (int k = -kHalf; k <= kHalf; ++k) {
        x0.push_back(a * s0);
        y0.push_back(b * s0);
        z0.push_back(k * s0);
      }
    }
  }
  const std::size_t n = x0.size(), c = (kHalf * kN + kHalf) * kN + kHalf;
  std::vector<double> x(n), y(n), z(n), vx(n), vy(n), vz(n), mass(n, m), rho(n), rho_n(n), h(n);
  std::vector<std::vector<double>> deps(6, std::vector<double>(n)), spin(3, std::vector<double>(n));
  for (std::size_t p = 0; p < n; ++p) {
    vx[p] = e * x0[p];
    vy[p] = e * y0[p];
    vz[p] = e * z0[p];
  }
  constexpr int kSteps = 200;
  const double dt = 0.5 / e / kSteps;
  double rho_i = rho_i0, t = 0.0;
  std::vector<std::uint32_t> nb;
  Expansion out;
  for (int step = 0; step < kSteps; ++step) {
    const double g = 1.0 + e * t, g_mid = 1.0 + e * (t + 0.5 * dt);
    for (std::size_t p = 0; p < n; ++p) {
      x[p] = x0[p] * g;
      y[p] = y0[p] * g;
      z[p] = z0[p] * g;
      rho[p] = rho_n[p] = rho0 / (g * g * g);
      h[p] = 1.2 * s0 * g_mid;  // h^{n+1/2} = h_factor (m / rho)^{1/3} at the midpoint
    }
    rho[c] = rho_n[c] = rho_i;
    h[c] = 1.2 * std::cbrt(m / rho_i);
    nb.clear();
    for (std::size_t j = 0; j < n; ++j) {
      const double d[3] = {x[c] - x[j], y[c] - y[j], z[c] - z[j]};
      const double reach = h[c] + h[j];
      if (j != c && d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < reach * reach) {
        nb.push_back(static_cast<std::uint32_t>(j));
      }
    }
    const ks::PairInputs in{x.data(),  y.data(),    z.data(),   vx.data(), vy.data(),
                            vz.data(), mass.data(), rho.data(), h.data()};
    ks::RateOutputs r;
    for (int k = 0; k < 6; ++k) r.deps[k] = deps[static_cast<std::size_t>(k)].data();
    for (int k = 0; k < 3; ++k) r.dspin[k] = spin[static_cast<std::size_t>(k)].data();
    r.rho = rho.data();
    r.rho_n = normalized ? rho_n.data() : nullptr;
    ks::rates_particle<double>(in, nb.data(), nb.size(), c, dt, r);
    rho_i = rho[c];
    t += dt;
    if (!(rho_i > 0.0)) {
      out.et_nonpositive = e * t;
      return out;
    }
  }
  const double g = 1.0 + e * t;
  out.ratio = rho_i / (rho_i0 / (g * g * g));
  return out;
}

TEST(SphContinuity, NormalizedFormKeepsALowDensityParticleInAnExpansionOnTheContinuum) {
  const Expansion standard = expand(false), normalized = expand(true);
  std::printf(
      "expansion: BA95 Eq. 16 reaches rho <= 0 at e t = %.4f; normalized rho / exact at "
      "e t = 0.5: %.4f\n",
      standard.et_nonpositive, normalized.ratio);
  // BA95's Eq. 16 sums the neighbours' mass: drho_i/dt ~ -rho_j div v, so
  // rho_i = rho_i(0) - rho0 (1 - (1 + e t)^-3), which is 0 at (1 + e t)^3 = 4/3, e t = 0.1006
  // (measured 0.1025: the lattice sum reads the divergence slightly low). This is the
  // mechanism of the lab impact's stop (docs/validation-sph.md). Bound: within 10 % of 0.1006.
  ASSERT_GT(standard.et_nonpositive, 0.0);
  EXPECT_NEAR(standard.et_nonpositive, 0.1006, 0.01);
  // The normalized form follows the continuum, rho_i / rho_i(0) = (1 + e t)^-3, to the lattice
  // sum's error in div v (measured ratio in the printout; the gradient of the cubic spline on a
  // lattice at h = 1.2 spacings reads ~1-2 % low, here over a density drop of 3.4x). Bound 3 %.
  ASSERT_LT(normalized.et_nonpositive, 0.0) << "the normalized form reached rho <= 0";
  EXPECT_NEAR(normalized.ratio, 1.0, 0.03);
}

// The switch's step (terms.hpp morris_monaghan_alpha) against the analytic solution of
// d alpha/dt = -(alpha - alpha_min) / tau + max(-div v, 0) (alpha_max - alpha) with frozen
// coefficients, over uneven steps (the composition of exact steps is exact; an explicit Euler
// step would miss by O(dt / tau) = 1e-2 here).
TEST(SphViscositySwitch, DecaysToAlphaMinAtTheRateOneOverTauWithoutCompression) {
  const ks::SwitchCoefficients k{0.1, 1.0, 0.1};
  const double c = 5000.0, h = 1e-3, tau = h / (k.decay * c);  // 2 us
  for (const double div_v : {0.0, 3e5}) {  // none, and an expansion (no source either)
    double alpha = 1.0, t = 0.0;
    for (int s = 0; t < 3.0 * tau; ++s) {
      const double dt = 1e-8 * (1.0 + 0.3 * (s % 7));
      alpha = ks::morris_monaghan_alpha(k, alpha, div_v, c, h, dt);
      t += dt;
    }
    const double exact = k.alpha_min + (1.0 - k.alpha_min) * std::exp(-t / tau);
    // Bound 1e-12: round-off over ~500 steps.
    EXPECT_NEAR(alpha, exact, 1e-12) << "div v = " << div_v;
  }
}

TEST(SphViscositySwitch, RisesTowardAlphaMaxInACompressionAndStaysWithinItsBounds) {
  const ks::SwitchCoefficients k{0.1, 1.0, 0.1};
  const double c = 5000.0, h = 1e-3, inv_tau = k.decay * c / h;  // 5e5 /s
  const double div_v = -2e6;                                     // compression, 1/s
  const double rate = inv_tau - div_v;
  const double a_eq = (k.alpha_min * inv_tau - div_v * k.alpha_max) / rate;  // 0.82
  double alpha = k.alpha_min, t = 0.0;
  for (int s = 0; s < 200; ++s) {
    const double dt = 5e-9 * (1.0 + 0.5 * (s % 3));
    alpha = ks::morris_monaghan_alpha(k, alpha, div_v, c, h, dt);
    t += dt;
  }
  const double exact = a_eq + (k.alpha_min - a_eq) * std::exp(-rate * t);
  EXPECT_NEAR(alpha, exact, 1e-12);
  EXPECT_GT(alpha, 0.8);  // close to a_eq = 0.82 after ~3 / rate
  // A shock: |div v| dt = 1e4, where an explicit step would overshoot alpha_max tenthousandfold.
  const double shocked = ks::morris_monaghan_alpha(k, k.alpha_min, -1e12, c, h, 1e-8);
  EXPECT_LE(shocked, k.alpha_max);
  EXPECT_GT(shocked, 0.999);
}

std::unique_ptr<Solver> make(const scene::Scene& s, int threads) {
  scene::BuiltScene b = scene::build(s);
  return scene::make_solver(s, std::move(b.particles), b.materials, threads);
}

const std::string kVerificationDir = std::string(SHATTER_SOURCE_DIR) + "/scenes/verification";
const std::vector<std::string> kSwitch = {"solver.sph.viscosity_switch=\"morris_monaghan\""};

// An elastic sphere (verification catalogue, c_p = 1.16 m/s, 0.05 m spacing) translating at
// 0.1 m/s: an uncompressed flow, div v = 0 exactly, so each particle's alpha must follow
// alpha_min + (alpha_max - alpha_min) exp(-t / tau) with its own tau = h / (C c).
TEST(SphViscositySwitch, SolverAlphaDecaysAtOneOverTauInAnUncompressedFlow) {
  const char* text = R"(
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
velocity = [0.1, 0.0, 0.0]
)";
  const scene::Scene s = scene::parse_scene(text, "sphere.toml", kSwitch, kVerificationDir);
  auto sim = make(s, 2);
  const auto& sph = dynamic_cast<const SphSolver&>(*sim);
  ASSERT_EQ(sph.viscosity_alpha().size(), sim->particles().size());
  for (int k = 0; k < 100; ++k) sim->step();  // past re-orders (every 25 steps)
  const double t = sim->time();
  const auto c = sim->particles().col(Field::soundspeed);
  const auto alpha = sph.viscosity_alpha();
  const auto h = sph.smoothing_length();
  const SphConfig& cfg = sph.sph_config();
  double worst = 0.0, decay = 0.0;
  for (std::size_t p = 0; p < alpha.size(); ++p) {
    const double e = std::exp(-t * cfg.switch_decay * c[p] / h[p]);
    const double exact = cfg.alpha_min + (cfg.alpha_max - cfg.alpha_min) * e;
    worst = std::max(worst, std::abs(alpha[p] - exact));
    decay = std::max(decay, e);
  }
  std::printf("translating sphere: t = %.3f s (%.2f tau), worst |alpha - exact| %.1e\n", t,
              -std::log(decay), worst);
  EXPECT_LT(decay, 0.3);    // the test covers a real decay (over more than a tau)
  EXPECT_LT(worst, 1e-12);  // round-off over 100 exact steps
}

// Two elastic spheres meeting head-on (the solver test's pair, 0.05 m spacing): total energy is
// conserved with the switch and the normalized continuity. (The
// spheres are soft, |div v| tau ~ 0.5, so the source barely lifts alpha above its decay here:
// the printout; the impact test below is where it rises.)
TEST(SphViscositySwitch, CollidingSpheresConserveEnergyWithTheSwitch) {
  const char* text = test::kSphCollidingSpheres;
  // The normalized continuity only (with the standard one the error measured 3.8e-5, as with
  // the constant viscosity; left out to keep the test cheap under the sanitizers).
  for (const char* continuity : {"normalized"}) {
    std::vector<std::string> set = kSwitch;
    set.push_back(std::string("solver.sph.continuity=\"") + continuity + "\"");
    const scene::Scene s = scene::parse_scene(text, "spheres.toml", set, kVerificationDir);
    auto sim = make(s, 2);
    const auto& sph = dynamic_cast<const SphSolver&>(*sim);
    const double ke0 = sim->energy().kinetic;
    double ke_min = ke0, max_err = 0.0, alpha_contact = 0.0, alpha_far = 0.0;
    while (sim->time() < 0.9) {
      sim->step();
      max_err = std::max(max_err, std::abs(sim->energy().error()));
      if (sim->energy().kinetic < ke_min) {
        // At the deepest compression: alpha near the contact point (0.43, 0.43, 0.43) against
        // that at the spheres' far sides.
        ke_min = sim->energy().kinetic;
        const ParticleStore& P = sim->particles();
        alpha_contact = alpha_far = 0.0;
        for (std::size_t p = 0; p < P.size(); ++p) {
          const double d =
              (P.col(Field::x)[p] + P.col(Field::y)[p] + P.col(Field::z)[p] - 3.0 * 0.43) /
              std::sqrt(3.0);
          if (std::abs(d) < 0.05) alpha_contact = std::max(alpha_contact, sph.viscosity_alpha()[p]);
          if (std::abs(d) > 0.15) alpha_far = std::max(alpha_far, sph.viscosity_alpha()[p]);
        }
      }
    }
    std::printf(
        "spheres, switch, %s continuity: KE_min/KE0 %.3f, at it max alpha %.3f at the "
        "contact, %.3f far from it; max energy error %.2e\n",
        continuity, ke_min / ke0, alpha_contact, alpha_far, max_err);
    EXPECT_LT(ke_min, 0.8 * ke0);  // the contact happened
    // Energy: measured 3.8e-5 (standard, as the constant viscosity's 3.8e-5) and 2.6e-4
    // (normalized: the (sigma_i + sigma_j) / (rho_i rho_j) pair conserves energy exactly in the
    // semi-discrete equations, the rest is time integration at a 0.05 m spacing); bound 5e-4.
    EXPECT_LT(max_err, 5e-4) << continuity;
  }
}

TEST(SphViscositySwitch, ThreadCountGivesTheSameBitsWithMirrorsAndIsRefusedOnResume) {
  // The half model of the small impact (mirror particles carry alpha), both new settings on,
  // 30 steps (one re-order): 1 and 2 threads bitwise.
  const std::string text = test::sph_impact_scene({.solver = "symmetry_plane = \"z\"\n"});
  std::vector<std::string> set = kSwitch;
  set.push_back("solver.sph.continuity=\"normalized\"");
  const scene::Scene s = scene::parse_scene(text, "impact.toml", set);
  auto a = make(s, 2), b = make(s, 1);
  for (int k = 0; k < 30; ++k) {
    a->step();
    b->step();
  }
  const auto& sa = dynamic_cast<const SphSolver&>(*a);
  const auto& sb = dynamic_cast<const SphSolver&>(*b);
  ASSERT_EQ(sa.viscosity_alpha().size(), sb.viscosity_alpha().size());
  std::size_t differ = 0;
  for (std::size_t p = 0; p < sa.viscosity_alpha().size(); ++p) {
    differ += sa.viscosity_alpha()[p] != sb.viscosity_alpha()[p] ? 1 : 0;
    differ += a->particles().col(Field::vx)[p] != b->particles().col(Field::vx)[p] ? 1 : 0;
    differ += a->particles().col(Field::rho)[p] != b->particles().col(Field::rho)[p] ? 1 : 0;
  }
  EXPECT_EQ(differ, 0u);
  EXPECT_EQ(a->energy().kinetic, b->energy().kinetic);
  const auto [lo, hi] =
      std::minmax_element(sa.viscosity_alpha().begin(), sa.viscosity_alpha().end());
  EXPECT_GE(*lo, 0.1);  // alpha_min, alpha_max
  EXPECT_LE(*hi, 1.0);
  std::printf("impact, switch + normalized, 30 steps (t = %.2e s): alpha in [%.3f, %.3f]\n",
              a->time(), *lo, *hi);
  // alpha is not in a checkpoint: resuming must fail with a message, not restart it silently.
  try {
    a->restore(a->clock(), a->energy());
    FAIL() << "a resume with the switch was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("viscosity_switch"), std::string::npos) << e.what();
  }
  // Bad settings are refused by the scene reader, naming the key.
  EXPECT_THROW(scene::parse_scene(text, "impact.toml", {"solver.sph.viscosity_switch=\"cd\""}),
               scene::SceneError);
  EXPECT_THROW(scene::parse_scene(text, "impact.toml",
                                  {"solver.sph.alpha_min=0.5", "solver.sph.alpha_max=0.2"}),
               scene::SceneError);
  EXPECT_THROW(scene::parse_scene(text, "impact.toml", {"solver.sph.continuity=\"mass\""}),
               scene::SceneError);
}

}  // namespace
}  // namespace shatter::sph
