#pragma once
// The constitutive update of one material group (MPM paper App. A.2 step 7), composed at compile
// time from an equation of state, a strength model and a damage policy, so that the inner loop
// has no model branches. It runs in xsimd batches over the group's columns with a scalar tail;
// the scalar path (T = double) is the reference the SIMD path is tested against.
//
// Per particle:
//  1. Jaumann rotation and elastic trial of the deviator (Eqs. 22, 35-37).
//  2. Energy predictor E* = E^n + deps : sigma^n / rho (App. A.2 step 7).
//  3. EOS at (rho^{n+1}, E*): pressure and c_K (Eqs. 8-12); intact c_p (Eq. 13).
//  4. Plastic return of the strength model (App. B, Eqs. 4-6, 41-49), plastic strain and heat.
//  5. Artificial viscosity q on compression.
//  6. Damage: the policy evolves D from the intact stress (kernels/damage).
//  7. Effective stress sigma = (1-D) s - (p* + q) I, p* = (1-D) p in tension (Eq. 14).
//  8. Energy corrector E^{n+1} = E^n + deps : (sigma^n + sigma^{n+1})/2 / rho (A.2 step 7).
//  9. Sound speed for the time step (Eq. 34): Eq. 13 with the damaged shear modulus (1-D) G.

#include <cstddef>

#include "constitutive/artificial_viscosity.hpp"
#include "constitutive/simd.hpp"
#include "damage/damage_policy.hpp"
#include "strength/jaumann.hpp"
#include "strength/strength_common.hpp"

namespace shatter::constitutive {

// Raw column pointers of the particle store (index p is particle p). Optional columns are null
// when the model does not use them.
struct ConstitutiveColumns {
  const double* rho = nullptr;
  const double* mass = nullptr;
  double* energy = nullptr;
  double* stress[6] = {};
  double* pressure = nullptr;
  double* soundspeed = nullptr;
  const double* deps[6] = {};
  const double* dspin[3] = {};
  double* sdev[6] = {};  // undamaged deviator (damage on)
  double* plastic_strain = nullptr;
  double* heat = nullptr;
  // damage, eps_min, eps_max, n_flaws, weibull_m, n_active
  double* damage_state[6] = {};
};

struct StepParams {
  double dt = 0.0;
  double cell_size = 0.0;
  double c_linear = 0.0;
  double c_quadratic = 0.0;
};

// deps : sigma for symmetric tensors in Voigt order with tensor shear components.
template <class T>
inline T double_contraction(const T (&a)[6], const T (&b)[6]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + 2.0 * (a[3] * b[3] + a[4] * b[4] + a[5] * b[5]);
}

template <class Eos, class Strength, class Damage>
class ComposedKernel {
 public:
  static constexpr bool kDamaged = Damage::kEnabled;

  ComposedKernel(Eos eos, Strength strength, Damage damage)
      : eos_(eos), strength_(strength), damage_(damage) {}

  const Eos& eos() const { return eos_; }
  const Strength& strength() const { return strength_; }
  const Damage& damage() const { return damage_; }

  // Updates particles [begin, end): batches of simd::kWidth, then a scalar tail. With
  // use_simd = false every particle takes the scalar path (reference and benchmark baseline).
  void update(const ConstitutiveColumns& c, std::size_t begin, std::size_t end,
              const StepParams& sp, bool use_simd = true) const {
    std::size_t p = begin;
    if (use_simd) {
      for (; p + simd::kWidth <= end; p += simd::kWidth) step<simd::Batch>(c, p, sp);
    }
    for (; p < end; ++p) step<double>(c, p, sp);
  }

  // Consistent initial state: p and c from (rho, E), effective stress from the stored deviator
  // and damage (Eq. 14). No increments are read.
  void initialise(const ConstitutiveColumns& c, std::size_t begin, std::size_t end) const {
    for (std::size_t p = begin; p < end; ++p) {
      double s[6];
      load_deviator<double>(c, p, s);
      const double rho = c.rho[p];
      const auto e = eos_.evaluate(rho, c.energy[p]);
      const double D = simd::load_or<double>(ptr(c.damage_state[0], p), 0.0);
      if constexpr (!Strength::kHasShear) {
        for (auto& x : s) x = 0.0;
      }
      if constexpr (Damage::kEnabled) {
        for (int k = 0; k < 6; ++k) c.sdev[k][p] = s[k];
      }
      double sig[6];
      effective_stress(s, e.p, 0.0, D, sig);
      for (int k = 0; k < 6; ++k) c.stress[k][p] = sig[k];
      c.pressure[p] = e.p;
      c.soundspeed[p] = longitudinal_speed(e.c2, rho, D);
    }
  }

  // Eq. 13: c_p = sqrt(4G/(3 rho) + c_K^2) of the intact material (damage = 0), or of material
  // with damage D, whose deviatoric stress is (1 - D) s (Eq. 14): its shear stiffness is
  // (1 - D) G, so c_p^2 = 4 (1 - D) G / (3 rho) + c_K^2. Fully damaged debris (D = 1) carries
  // no shear wave; with the intact G its shear term grows like 1/rho as it expands (39 km/s for
  // basalt at rho = 20 kg/m^3) and sets a needlessly short step. The bulk term stays whole: in
  // compression Eq. 14 keeps p; in tension p* = (1 - D) p would lower c_K too, and keeping the
  // intact c_K there only errs on the safe (shorter-step) side.
  template <class T>
  T longitudinal_speed(const T& c2, const T& rho, const T& damage = T(0.0)) const {
    return simd::vsqrt(c2 + (4.0 / 3.0) * strength_.elastic.G * (1.0 - damage) / rho);
  }

  template <class T>
  void step(const ConstitutiveColumns& c, std::size_t p, const StepParams& sp) const {
    using simd::load_col;
    using simd::load_or;
    using simd::store_col;
    using simd::store_if;
    using simd::vselect;

    const T rho = load_col<T>(c.rho + p);
    const T e_old = load_col<T>(c.energy + p);
    T de[6], w[3], sig_old[6], s[6];
    for (int k = 0; k < 6; ++k) de[k] = load_col<T>(c.deps[k] + p);
    for (int k = 0; k < 3; ++k) w[k] = load_col<T>(c.dspin[k] + p);
    for (int k = 0; k < 6; ++k) sig_old[k] = load_col<T>(c.stress[k] + p);
    load_deviator<T>(c, p, s);
    const T d_old = load_or<T>(ptr(c.damage_state[0], p), 0.0);

    // 1. Jaumann rotation + elastic trial (Eqs. 22, 35-37).
    if constexpr (Strength::kHasShear) {
      strength::jaumann_trial(s, de, w, strength_.elastic.G);
    }

    // 2. Energy predictor. The engine sets rho^{n+1} = rho^n / (1 + tr deps), i.e. the volume
    // grows by tr(deps) V^n, so the work per unit mass is deps : sigma V^n / m = deps : sigma /
    // rho^n: with this density the energy change matches the engine's volume change exactly
    // (for a gas, dE = -p dV/m with no O(tr deps) bias).
    const T tr = de[0] + de[1] + de[2];
    const T rho_old = rho * (1.0 + tr);
    const T w_old = double_contraction(de, sig_old);
    const T e_trial = e_old + w_old / rho_old;

    // 3. EOS (Eqs. 8-12).
    const auto st_eos = eos_.evaluate(rho, e_trial);

    // 4. Plastic return.
    strength::PlasticState<T> ps{st_eos.p,
                                 load_or<T>(ptr(c.plastic_strain, p), 0.0),
                                 load_or<T>(ptr(c.heat, p), 0.0),
                                 d_old,
                                 rho,
                                 e_trial,
                                 T(0.0)};
    strength_.return_map(s, ps);
    const T pres = ps.p;

    // Eq. 13 of the intact material: the crack speed c_g = 0.4 c_p of Eq. 19 is that of a crack
    // tip running through the intact matrix between the cracks (BA95 Sec. 3), not a property of
    // the damaged particle as a whole; with (1 - D) G a particle's cracks would slow down as it
    // fails (to 0.4 c_K at D = 1), a feedback the Grady-Kipp model does not have. The viscosity
    // below uses the bulk c_K, which damage does not change in compression.
    const T cp = longitudinal_speed(st_eos.c2, rho);

    // 5. Artificial viscosity.
    const double inv_dt = sp.dt > 0.0 ? 1.0 / sp.dt : 0.0;
    const auto av = artificial_viscosity(tr, inv_dt, sp.cell_size, rho, simd::vsqrt(st_eos.c2),
                                         sp.c_linear, sp.c_quadratic);

    // 6. Damage from the intact stress.
    T dmg = T(0.0);
    if constexpr (Damage::kEnabled) {
      damage::DamageInput<T> in;
      for (int k = 0; k < 6; ++k) in.s[k] = s[k];
      for (int k = 0; k < 3; ++k) in.s[k] = in.s[k] - pres;
      in.young = T(strength_.elastic.young);
      in.soundspeed = cp;
      in.volume = load_or<T>(ptr(c.mass, p), 0.0) / rho;
      in.dplastic = ps.deps_p;
      in.dt = sp.dt;
      damage::DamageState<T> ds;
      T* fields[6] = {&ds.damage,  &ds.eps_min,   &ds.eps_max,
                      &ds.n_flaws, &ds.weibull_m, &ds.n_active};
      for (int k = 0; k < 6; ++k) *fields[k] = load_or<T>(ptr(c.damage_state[k], p), 0.0);
      dmg = damage_.evolve(in, ds);
      ds.damage = dmg;
      for (int k = 0; k < 6; ++k) store_if(ptr(c.damage_state[k], p), *fields[k]);
      for (int k = 0; k < 6; ++k) store_col(c.sdev[k] + p, s[k]);
    }

    // 7. Effective stress (Eq. 14) with the viscous pressure.
    T sig[6];
    effective_stress(s, pres, av.q, dmg, sig);
    for (int k = 0; k < 6; ++k) store_col(c.stress[k] + p, sig[k]);

    // 8. Energy corrector: midpoint stress sigma^{n+1/2} = (sigma^n + sigma^{n+1}) / 2.
    const T w_new = double_contraction(de, sig);
    store_col(c.energy + p, e_old + 0.5 * (w_old + w_new) / rho_old);

    // 9. Eq. 13 with the damage of the stress just stored (Eq. 14), (1 - D^{n+1}) G, for the
    // time step (Eq. 34): D never decreases, so the next step's stress is no stiffer than this.
    const T cp_damaged = Damage::kEnabled ? longitudinal_speed(st_eos.c2, rho, dmg) : cp;
    store_col(c.pressure + p, pres);
    store_col(c.soundspeed + p, cp_damaged + av.speed);
    store_if(ptr(c.plastic_strain, p), ps.eps_p);
    store_if(ptr(c.heat, p), ps.heat);
  }

 private:
  static double* ptr(double* base, std::size_t p) { return base != nullptr ? base + p : nullptr; }
  static const double* ptr(const double* base, std::size_t p) {
    return base != nullptr ? base + p : nullptr;
  }

  // The undamaged deviator at step n: the sdev columns when damage is on (the stress columns then
  // hold the damaged stress), else the deviatoric part of the stress (the viscous pressure and
  // the EOS pressure are isotropic, so they drop out).
  template <class T>
  static void load_deviator(const ConstitutiveColumns& c, std::size_t p, T (&s)[6]) {
    if constexpr (Damage::kEnabled) {
      for (int k = 0; k < 6; ++k) s[k] = simd::load_col<T>(c.sdev[k] + p);
    } else {
      for (int k = 0; k < 6; ++k) s[k] = simd::load_col<T>(c.stress[k] + p);
      const T m = (s[0] + s[1] + s[2]) * (1.0 / 3.0);
      for (int k = 0; k < 3; ++k) s[k] = s[k] - m;
    }
  }

  // Eq. 14: sigma = (1 - D) s - p* I, p* = (1 - D) p in tension, p otherwise; minus q I.
  template <class T>
  static void effective_stress(const T (&s)[6], const T& p, const T& q, const T& D, T (&sig)[6]) {
    const T one_d = 1.0 - D;
    const T p_eff = simd::vselect(p < 0.0, one_d * p, p) + q;
    for (int k = 0; k < 6; ++k) sig[k] = one_d * s[k];
    for (int k = 0; k < 3; ++k) sig[k] = sig[k] - p_eff;
  }

  Eos eos_;
  Strength strength_;
  Damage damage_;
};

}  // namespace shatter::constitutive
