// The sound speed of damaged material (MPM paper Eq. 13 with the stress of Eq. 14): the time step
// (Eq. 34) must see the shear stiffness the stress update applies, (1 - D) G, while the crack
// speed of Eq. 19 (c_g = 0.4 c_p) stays that of the intact matrix the cracks run through.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

#include "constitutive/composed_kernel.hpp"
#include "damage/damage_policy.hpp"
#include "eos/linear_elastic.hpp"
#include "strength/elastic.hpp"

namespace shatter {
namespace {

// A damage policy that keeps the damage it is given and records the sound speed the kernel hands
// it in n_active, so the test can read back what the crack speed of Eq. 19 would be built from.
struct SpyDamage {
  static constexpr FieldSet kFields{Field::damage, Field::n_active};
  static constexpr bool kEnabled = true;
  template <class T>
  T evolve(const damage::DamageInput<T>& in, damage::DamageState<T>& st) const {
    st.n_active = in.soundspeed;
    return st.damage;
  }
};

constexpr double kRho0 = 2700.0, kK = 50e9;
const auto kEl = strength::ElasticConstants::from_young_poisson(60e9, 0.25);

using Kernel = constitutive::ComposedKernel<eos::LinearElastic, strength::Elastic, SpyDamage>;

// Columns of n particles with damage D[p] and density rho[p], at rest and unstrained.
struct Store {
  std::vector<std::vector<double>> c;
  explicit Store(const std::vector<double>& D, const std::vector<double>& rho)
      : c(40, std::vector<double>(D.size(), 0.0)) {
    c[0] = rho;
    for (std::size_t p = 0; p < D.size(); ++p) c[1][p] = rho[p] * 1e-9;  // mass of 1 mm^3
    c[30] = D;
  }
  constitutive::ConstitutiveColumns columns() {
    constitutive::ConstitutiveColumns k;
    k.rho = c[0].data();
    k.mass = c[1].data();
    k.energy = c[2].data();
    for (int i = 0; i < 6; ++i) k.stress[i] = c[3 + i].data();
    k.pressure = c[9].data();
    k.soundspeed = c[10].data();
    for (int i = 0; i < 6; ++i) k.deps[i] = c[11 + i].data();
    for (int i = 0; i < 3; ++i) k.dspin[i] = c[17 + i].data();
    for (int i = 0; i < 6; ++i) k.sdev[i] = c[20 + i].data();
    for (int i = 0; i < 6; ++i) k.damage_state[i] = c[30 + i].data();
    return k;
  }
  double soundspeed(std::size_t p) const { return c[10][p]; }
  double seen_by_damage(std::size_t p) const { return c[35][p]; }
};

// Damage 0, 1/2 and 1 at the reference density and at 1 % of it (expanded debris), repeated so
// that both the SIMD batches and the scalar tail run.
void cases(std::vector<double>& D, std::vector<double>& rho) {
  for (int k = 0; k < 5; ++k) {
    for (const double d : {0.0, 0.5, 1.0}) {
      for (const double r : {kRho0, 0.01 * kRho0}) {
        D.push_back(d);
        rho.push_back(r);
      }
    }
  }
}

double expected(double D, double rho, double G) {
  return std::sqrt(kK / kRho0 + (1.0 - D) * 4.0 * G / (3.0 * rho));
}

TEST(DamagedSoundSpeed, TimeStepSpeedUsesDamagedShearModulus) {
  std::vector<double> D, rho;
  cases(D, rho);
  const Kernel kernel(eos::LinearElastic({kRho0, kK}), strength::Elastic{kEl}, SpyDamage{});
  // No strain (so no viscosity and no change of D or rho): Eq. 13 at the given state.
  const constitutive::StepParams sp{1e-8, 1e-3, 0.0, 0.0};
  for (const bool simd : {true, false}) {
    Store s(D, rho);
    kernel.update(s.columns(), 0, D.size(), sp, simd);
    for (std::size_t p = 0; p < D.size(); ++p) {
      // 1e-14 relative: a square root of a sum of two terms, one ulp each.
      EXPECT_NEAR(s.soundspeed(p), expected(D[p], rho[p], kEl.G), 1e-14 * s.soundspeed(p))
          << "D = " << D[p] << ", rho = " << rho[p] << ", simd " << simd;
    }
  }
  // A fully damaged particle at 1 % of rho0 carries no shear wave: its speed is the bulk one,
  // sqrt(K / rho0) = 4.3 km/s, not the 34.7 km/s of the intact G at that density.
  Store s(D, rho);
  kernel.update(s.columns(), 0, D.size(), sp, true);
  EXPECT_NEAR(s.soundspeed(5), std::sqrt(kK / kRho0), 1e-9);
  EXPECT_LT(s.soundspeed(5), 5e3);
}

TEST(DamagedSoundSpeed, InitialStateUsesDamagedShearModulus) {
  std::vector<double> D, rho;
  cases(D, rho);
  const Kernel kernel(eos::LinearElastic({kRho0, kK}), strength::Elastic{kEl}, SpyDamage{});
  Store s(D, rho);
  kernel.initialise(s.columns(), 0, D.size());
  for (std::size_t p = 0; p < D.size(); ++p) {
    EXPECT_NEAR(s.soundspeed(p), expected(D[p], rho[p], kEl.G), 1e-14 * s.soundspeed(p))
        << "D = " << D[p] << ", rho = " << rho[p];
  }
}

TEST(DamagedSoundSpeed, CrackSpeedKeepsIntactShearModulus) {
  // c_g = 0.4 c_p of Eq. 19 is the speed of a crack tip through the intact matrix between the
  // cracks (BA95 Sec. 3): the damage policy must see the intact c_p whatever D is.
  std::vector<double> D, rho;
  cases(D, rho);
  const Kernel kernel(eos::LinearElastic({kRho0, kK}), strength::Elastic{kEl}, SpyDamage{});
  const constitutive::StepParams sp{1e-8, 1e-3, 0.0, 0.0};
  for (const bool simd : {true, false}) {
    Store s(D, rho);
    kernel.update(s.columns(), 0, D.size(), sp, simd);
    for (std::size_t p = 0; p < D.size(); ++p) {
      EXPECT_NEAR(s.seen_by_damage(p), expected(0.0, rho[p], kEl.G), 1e-14 * s.seen_by_damage(p))
          << "D = " << D[p] << ", rho = " << rho[p] << ", simd " << simd;
    }
  }
}

}  // namespace
}  // namespace shatter
