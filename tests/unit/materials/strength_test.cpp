// Return mappings of the strength models (MPM paper App. B, Sec. 3.1).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "strength/benz_asphaug.hpp"
#include "strength/drucker_prager.hpp"
#include "strength/j2_plasticity.hpp"
#include "strength/jaumann.hpp"
#include "strength/lundborg.hpp"
#include "strength/modified_lundborg.hpp"

namespace shatter {
namespace {

using strength::ElasticConstants;
using strength::PlasticState;

const ElasticConstants kBasalt = ElasticConstants::from_young_poisson(53.1e9, 0.15);

PlasticState<double> state(double p, double damage = 0.0) {
  return {p, 0.0, 0.0, damage, 2700.0, 0.0, 0.0};
}

// A pure-shear deviator with tau = sqrt(J2) = t.
void shear(double (&s)[6], double t) {
  for (auto& c : s) c = 0.0;
  s[3] = t;
}

// Deviatoric strain increment (pure shear) driven through the Jaumann trial.
void load_shear(double (&s)[6], double gamma, double G) {
  const double de[6] = {0, 0, 0, gamma, 0, 0};
  const double w[3] = {0, 0, 0};
  strength::jaumann_trial(s, de, w, G);
}

double tau(const double (&s)[6]) {
  return std::sqrt(strength::j2(s));
}

TEST(J2Plasticity, RadialReturnLandsOnTheHardenedSurface) {
  // Eq. 43: deps = f/(3G + Ep); after return sigma_bar = Y + Ep eps_bar to round-off
  // (1e-12 relative of the 3.5 GPa yield: a handful of ulp through sqrt and one division).
  const strength::J2Plasticity m{kBasalt, 3.5e9, 5.31e9};
  double s[6];
  shear(s, 4e9);  // sigma_bar* = sqrt(3) 4 GPa > 3.5 GPa
  auto st = state(1e9);
  const double sbar_trial = std::sqrt(3.0) * 4e9;
  m.return_map(s, st);
  const double sbar = std::sqrt(3.0) * tau(s);
  EXPECT_NEAR(st.deps_p, (sbar_trial - 3.5e9) / (3.0 * kBasalt.G + 5.31e9), 1e-15);
  EXPECT_NEAR(sbar, 3.5e9 + 5.31e9 * st.eps_p, 1e-12 * 3.5e9);
  EXPECT_GT(st.heat, 0.0);
  // Eq. 40 for J2 flow: dQ = sigma_bar deps_bar (per unit mass: / rho).
  EXPECT_NEAR(st.heat, sbar * st.deps_p / 2700.0, 1e-12 * st.heat);
}

TEST(J2Plasticity, StaysOnSurfaceUnderContinuedLoading) {
  // Perfect plasticity (Eq. 42): 50 further shear increments keep f = 0 to 1e-12 relative.
  const strength::J2Plasticity m{kBasalt, 3.5e9, 0.0};
  double s[6];
  shear(s, 0.0);
  auto st = state(0.0);
  for (int i = 0; i < 100; ++i) {
    load_shear(s, 2e-3, kBasalt.G);
    m.return_map(s, st);
    if (i > 50) {
      EXPECT_NEAR(std::sqrt(3.0) * tau(s), 3.5e9, 1e-12 * 3.5e9) << i;
    }
  }
  EXPECT_GT(st.eps_p, 0.0);
}

TEST(J2Plasticity, ElasticStateIsUntouched) {
  const strength::J2Plasticity m{kBasalt, 3.5e9, 0.0};
  double s[6];
  shear(s, 1e9);
  auto st = state(0.0);
  m.return_map(s, st);
  EXPECT_EQ(s[3], 1e9);
  EXPECT_EQ(st.eps_p, 0.0);
  EXPECT_EQ(st.heat, 0.0);
}

TEST(BenzAsphaug, ScalesDeviatorByEq9) {
  // f = min(Y0^2/(3 J2), 1) (BA95 Eq. 9), exact up to one rounding.
  const strength::BenzAsphaug m{kBasalt, 3.5e9};
  double s[6];
  shear(s, 4e9);
  auto st = state(0.0);
  m.return_map(s, st);
  const double f = 3.5e9 * 3.5e9 / (3.0 * 4e9 * 4e9);
  EXPECT_NEAR(s[3], 4e9 * f, 1e-15 * 4e9);
  EXPECT_GT(st.eps_p, 0.0);
  EXPECT_GE(st.heat, 0.0);
  shear(s, 1e9);  // below yield: f = 1
  m.return_map(s, st);
  EXPECT_EQ(s[3], 1e9);
}

TEST(DruckerPrager, ShearReturnWithDilatancy) {
  // Eqs. 44-46: lands on f_s = 0, p = p* + K q_psi dlambda, tau = tau* - G dlambda (exact for a
  // linear surface; 1e-9 relative of the strength covers the rounding of G dlambda ~ tau*).
  const strength::DruckerPrager m{kBasalt, 50e6, 0.6, 0.2, -30e6};
  double s[6];
  shear(s, 800e6);
  auto st = state(500e6);
  m.return_map(s, st);
  const double dl = (800e6 - 0.6 * 500e6 - 50e6) / (kBasalt.G + kBasalt.K * 0.6 * 0.2);
  EXPECT_NEAR(st.p, 500e6 + kBasalt.K * 0.2 * dl, 1e-9 * 500e6);
  EXPECT_NEAR(tau(s), 0.6 * st.p + 50e6, 1e-9 * 350e6);
  EXPECT_GE(st.heat, 0.0);
}

TEST(DruckerPrager, TensionCutOffAndCorner) {
  const strength::DruckerPrager m{kBasalt, 50e6, 0.6, 0.2, -30e6};
  double s[6];
  shear(s, 10e6);  // below the corner strength 0.6 * -30 + 50 = 32 MPa
  auto st = state(-100e6);
  m.return_map(s, st);
  EXPECT_EQ(st.p, -30e6);
  EXPECT_EQ(s[3], 10e6);
  shear(s, 100e6);  // above: capped at the corner
  st = state(-100e6);
  m.return_map(s, st);
  EXPECT_NEAR(tau(s), 32e6, 1e-6);
  EXPECT_GT(st.eps_p, 0.0);
}

TEST(Lundborg, IntactAndDamagedBranches) {
  // Eqs. 47-49 at p = 1 GPa: Y_i = Y0 + mu_i p / (1 + mu_i p / (Ym - Y0)); Y_d = mu_d p capped
  // at Y_i; Y = (1-D) Y_i + D Y_d.
  const strength::Lundborg m{kBasalt, 90e6, 1.5, 0.8, 1500e6, 0.0};
  const double p = 1e9;
  const double yi = 90e6 + 1.5 * p / (1.0 + 1.5 * p / (1500e6 - 90e6));
  const double yd = std::min(0.8 * p, yi);
  for (double d : {0.0, 0.3, 1.0}) {
    EXPECT_NEAR(m.yield(p, d, 0.0), (1 - d) * yi + d * yd, 1e-6) << d;
  }
  // Tensile strength of intact rock, p_t = -Y0 (Ym - Y0)/(mu_i Ym): zero strength there and below.
  EXPECT_NEAR(m.yield(m.intact_tension(), 0.0, 0.0), 0.0, 1e-6);
  EXPECT_EQ(m.yield(-1e9, 0.0, 0.0), 0.0);
  double s[6];
  shear(s, 2e9);
  auto st = state(p);
  m.return_map(s, st);
  EXPECT_NEAR(tau(s), yi, 1e-9 * yi);
}

TEST(Lundborg, MeltSoftening) {
  const strength::Lundborg m{kBasalt, 90e6, 1.5, 0.8, 1500e6, 3.4e6};
  EXPECT_NEAR(m.yield(1e9, 0.0, 1.7e6), 0.5 * m.yield(1e9, 0.0, 0.0), 1e-6);
  EXPECT_EQ(m.yield(1e9, 0.0, 5e6), 0.0);
}

// Tension cut-off of the Lundborg surface (material key tension_cutoff; lundborg.hpp): below
// p_t the pressure is clipped to p_t and Y taken there; at and above p_t, and without the key,
// the return is the original one bit for bit.
TEST(Lundborg, TensionCutOffActsBelowPtAndNowhereElse) {
  // The granular target of scenes/porosity (cohesion 1 Pa, friction 0.6, Ym 1 GPa).
  const strength::Lundborg off{kBasalt, 1.0, 0.6, 0.6, 1e9, 0.0};
  EXPECT_FALSE(off.has_tension_cutoff());  // the default: no cut-off
  for (double pt : {0.0, -20e6}) {
    strength::Lundborg on = off;
    on.tension_cutoff = pt;
    ASSERT_TRUE(on.has_tension_cutoff());
    for (double p : {-1e9, -50e6, -20e6, -1.0, 0.0, 1e6, 300e6, 5e9}) {
      for (double d : {0.0, 1.0}) {
        for (double t : {0.0, 1e6, 2e9}) {
          double s_off[6], s_on[6];
          shear(s_off, t);
          shear(s_on, t);
          auto st_off = state(p, d), st_on = state(p, d);
          st_off.heat = st_on.heat = 7.0;
          off.return_map(s_off, st_off);
          on.return_map(s_on, st_on);
          // Without the key: the pressure is never touched (the original return).
          EXPECT_EQ(st_off.p, p);
          if (p >= pt) {
            // At and above p_t the cut-off changes nothing, bit for bit.
            EXPECT_EQ(st_on.p, st_off.p) << p;
            EXPECT_EQ(s_on[3], s_off[3]) << p;
            EXPECT_EQ(st_on.heat, st_off.heat) << p;
            EXPECT_EQ(st_on.eps_p, st_off.eps_p) << p;
          } else {
            // Below: p = p_t, tau = min(tau*, Y(p_t)) (Eqs. 47-49 at the clipped pressure), and
            // the return's work (Eq. 40) booked with the pressure change p_t - p*.
            EXPECT_EQ(st_on.p, pt) << p;
            const double y = on.yield(pt, d, 0.0);
            EXPECT_EQ(tau(s_on), std::min(t, y)) << p;
            const double dtau = t - tau(s_on), dp = pt - p;
            const double dq = tau(s_on) * dtau / kBasalt.G - pt * dp / kBasalt.K;
            EXPECT_NEAR(st_on.heat, 7.0 + std::max(dq, 0.0) / 2700.0, 1e-12 * st_on.heat) << p;
            const double eps = std::sqrt(2.0 / 3.0 *
                                         (dtau * dtau / (2.0 * kBasalt.G * kBasalt.G) +
                                          dp * dp / (3.0 * kBasalt.K * kBasalt.K)));
            EXPECT_NEAR(st_on.deps_p, eps, 1e-12 * eps) << p;
          }
        }
      }
    }
  }
}

TEST(Lundborg, WithoutTheCutOffTheReturnIsTheOriginalOne) {
  // The return before the key existed, written out: tau = min(tau*, Y(p*)), s scaled, p kept.
  const strength::Lundborg m{kBasalt, 90e6, 1.5, 0.8, 1500e6, 3.4e6};
  for (double p : {-1e9, -30e6, 0.0, 1e8, 3e9}) {
    double s[6] = {1e8, -3e8, 2e8, 4e8, -1e8, 5e7};
    double s_ref[6];
    for (int k = 0; k < 6; ++k) s_ref[k] = s[k];
    auto st = state(p, 0.4);
    st.energy = 1e6;
    auto st_ref = st;
    m.return_map(s, st);
    const double tau_trial = std::sqrt(strength::j2(s_ref));
    const double t = std::min(tau_trial, m.yield(p, 0.4, 1e6));
    for (auto& c : s_ref) c = c * (t / std::max(tau_trial, strength::kTinyStress));
    strength::book_plastic_work(tau_trial, t, p, p, kBasalt, st_ref);
    for (int k = 0; k < 6; ++k) EXPECT_EQ(s[k], s_ref[k]) << p;
    EXPECT_EQ(st.p, p);
    EXPECT_EQ(st.heat, st_ref.heat);
    EXPECT_EQ(st.eps_p, st_ref.eps_p);
  }
}

// --- modified Lundborg (Sec. 3.1) ---

const strength::ModifiedLundborg kML{kBasalt, 90e6, 1.5, 0.8, 1500e6, 0.256, 3.4e6};

double f_ml(const strength::ModifiedLundborg& m, const double (&s)[6],
            const PlasticState<double>& st, double heat_before) {
  double y, h;
  m.yield(st.p, st.damage, m.melt_factor(heat_before), y, h);
  return tau(s) - y;  // Eq. 4
}

TEST(ModifiedLundborg, ReturnLandsOnSurfaceWithEq5) {
  // After Eq. 5 the state satisfies f = 0 (Eq. 4) at the corrected pressure to 1e-9 of the
  // strength scale (Newton converges to round-off: ~1e-16 * tau* * condition ~1e2).
  for (double d : {0.0, 0.5, 1.0}) {
    for (double p : {-50e6, 0.0, 100e6, 1e9, 5e9, 50e9}) {
      double s[6];
      shear(s, 3e9);
      auto st = state(p, d);
      st.heat = 1e5;
      const double p_trial = p;
      kML.return_map(s, st);
      EXPECT_LE(std::abs(f_ml(kML, s, st, 1e5)), 1e-9 * 3e9) << "D=" << d << " p=" << p;
      // Eq. 5b/5c: p - p* = K q_psi dl and tau* - tau = G dl give the same dl; dilatancy acts
      // only under confinement (p* > 0), so q_psi is 0 for the tension and zero-pressure states.
      const double q = p_trial > 0.0 ? 0.256 : 0.0;
      const double dl = (3e9 - tau(s)) / kBasalt.G;
      EXPECT_NEAR(st.p - p_trial, kBasalt.K * q * dl, 1e-9 * std::abs(p_trial) + 1e-3);
      // Eq. 6c: deps_bar = dl sqrt(1/3 + 2/9 q_psi^2), to 1e-12 relative.
      EXPECT_NEAR(st.deps_p, dl * std::sqrt(1.0 / 3.0 + 2.0 / 9.0 * q * q),
                  1e-12 * st.deps_p + 1e-18);
      EXPECT_GE(st.heat, 1e5);  // dQ >= 0 (Eq. 40 clamped)
    }
  }
}

TEST(ModifiedLundborg, DilatancyNeedsConfinement) {
  // Fully damaged debris in tension has no strength (Eq. 48 held at 0 for p < 0), so the whole
  // trial shear flows plastically. Before the confinement condition, Eq. 5b turned it into
  // K q_psi tau*/G of compression: 1.1 GPa from tau* = 3 GPa, which in the lab impact inflated
  // free-flying debris and shot it out at 9 km/s. Now p stays p* exactly and tau returns to 0.
  // Under confinement (p* = +1 MPa) the same shear must still dilate (p rises by > 100 MPa).
  for (double p : {-50e6, -1.0}) {
    double s[6];
    shear(s, 3e9);
    auto st = state(p, 1.0);
    kML.return_map(s, st);
    EXPECT_EQ(st.p, p);
    EXPECT_LE(tau(s), 1e-9 * 3e9);
  }
  double s[6];
  shear(s, 3e9);
  auto st = state(1e6, 1.0);
  kML.return_map(s, st);
  EXPECT_GT(st.p, 1e6 + 100e6);
}

TEST(ModifiedLundborg, TensionCutOffActsBelowPtAndNowhereElse) {
  // The same cut-off as Lundborg's: below p_t the corrector starts from p_t (no dilatancy there,
  // p_t <= 0) and returns to Eq. 4 at p_t; at and above p_t, bitwise the return without it.
  strength::ModifiedLundborg on = kML;
  on.tension_cutoff = -10e6;
  EXPECT_FALSE(kML.has_tension_cutoff());
  for (double p : {-1e9, -50e6, -10e6, 0.0, 100e6, 1e9}) {
    for (double d : {0.0, 1.0}) {
      double s_off[6], s_on[6];
      shear(s_off, 3e9);
      shear(s_on, 3e9);
      auto st_off = state(p, d), st_on = state(p, d);
      kML.return_map(s_off, st_off);
      on.return_map(s_on, st_on);
      if (p >= -10e6) {
        EXPECT_EQ(st_on.p, st_off.p) << p;
        EXPECT_EQ(s_on[3], s_off[3]) << p;
        EXPECT_EQ(st_on.heat, st_off.heat) << p;
      } else {
        EXPECT_EQ(st_off.p, p);  // no cut-off: tension kept
        EXPECT_EQ(st_on.p, -10e6) << p;
        double y, h;
        on.yield(-10e6, d, 1.0, y, h);
        EXPECT_NEAR(tau(s_on), y, 1e-9 * 3e9) << p;
      }
    }
  }
}

TEST(ModifiedLundborg, StaysOnSurfaceUnderContinuedLoading) {
  double s[6];
  shear(s, 0.0);
  auto st = state(200e6);
  int plastic_steps = 0;
  for (int i = 0; i < 200; ++i) {
    const double heat_before = st.heat;
    st.p = 200e6;  // EOS pressure held (confined shear)
    load_shear(s, 1e-3, kBasalt.G);
    const double t_trial = tau(s);
    kML.return_map(s, st);
    if (tau(s) < t_trial) {
      ++plastic_steps;
      EXPECT_LE(std::abs(f_ml(kML, s, st, heat_before)), 1e-9 * 1e9) << i;
    }
    EXPECT_GE(st.heat, heat_before) << i;
  }
  EXPECT_GT(plastic_steps, 150);
  EXPECT_GT(st.heat, 0.0);  // plastic work softens the surface (1 - Q/Q_melt)
}

TEST(ModifiedLundborg, YieldDerivativeIsContinuousAndMatchesDifferences) {
  // Eq. 4 is C1: H = dY/dp (Eq. 5a) equals the central difference of Y everywhere above the
  // tensile limit (5e-6 relative: truncation of a 1e-3 relative step on a curve with Ym scale),
  // and H has no jump across p = 0 (the kink of Drucker-Prager with a cut-off that Eq. 4 removes).
  for (double d : {0.0, 0.4}) {
    for (double p = kML.intact_tension() * 0.9; p < 20e9; p = p < 0 ? p * 0.5 + 1e6 : p * 1.5) {
      double y, h, yp, hp, ym, hm;
      const double dp = 1e-3 * (std::abs(p) + 1e6);
      kML.yield(p, d, 1.0, y, h);
      kML.yield(p + dp, d, 1.0, yp, hp);
      kML.yield(p - dp, d, 1.0, ym, hm);
      if (d > 0 && std::abs(p) < dp) continue;  // the damaged branch starts at p = 0
      EXPECT_NEAR(h, (yp - ym) / (2 * dp), 5e-6 * 1.5 + 1e-3 * std::abs(hp - hm)) << p;
    }
    double hl, hr, y;
    kML.yield(-1.0, 0.0, 1.0, y, hl);
    kML.yield(1.0, 0.0, 1.0, y, hr);
    EXPECT_NEAR(hl, hr, 1e-8);
  }
}

TEST(ModifiedLundborg, StiffAndExtremeStatesStayFinite) {
  // E_Y = 1e3 GPa, p ~ 1 TPa, trial shear of 1 TPa, deep tension: the fixed 12 Newton steps
  // must give a finite state on or inside the surface.
  const auto stiff = ElasticConstants::from_young_poisson(1e12, 0.25);
  const strength::ModifiedLundborg m{stiff, 90e6, 1.5, 0.8, 1500e6, 0.256, 3.4e6};
  for (double p : {-1e12, -1e9, 0.0, 1e9, 1e12}) {
    for (double t : {0.0, 1e6, 1e9, 1e12}) {
      for (double q : {0.0, 1e6, 1e7}) {
        double s[6];
        shear(s, t);
        auto st = state(p, 0.2);
        st.heat = q;
        m.return_map(s, st);
        ASSERT_TRUE(std::isfinite(st.p) && std::isfinite(s[3]) && std::isfinite(st.heat));
        double y, h;
        m.yield(st.p, 0.2, m.melt_factor(q), y, h);
        EXPECT_LE(tau(s), y * (1 + 1e-9) + 1e-3) << p << " " << t << " " << q;
        EXPECT_GE(tau(s), 0.0);
      }
    }
  }
}

TEST(Jaumann, RigidRotationRotatesTheDeviator) {
  // Eq. 22 for a rigid spin theta about z (vx = -w y, vy = w x: W_xy = -w dt) applied to a
  // uniaxial deviator diag(2, -1, -1): to first order the xy component becomes 3 theta.
  double s[6] = {2.0, -1.0, -1.0, 0.0, 0.0, 0.0};
  const double theta = 1e-4;
  const double de[6] = {0, 0, 0, 0, 0, 0};
  const double w[3] = {-theta, 0.0, 0.0};
  strength::jaumann_trial(s, de, w, 1.0);
  EXPECT_NEAR(s[3], 3.0 * theta, 1e-15);
  EXPECT_NEAR(s[0] + s[1] + s[2], 0.0, 1e-15);
  // Invariant under rotation to second order: J2 changes by O(theta^2).
  EXPECT_NEAR(strength::j2(s), 3.0, 1e-7);
}

}  // namespace
}  // namespace shatter
