#pragma once
// The constitutive update of one material group (MPM paper App. A.2 step 7), composed at compile
// time from an equation of state, a strength model and a damage policy, so that the inner loop
// has no model branches. It runs in xsimd batches over the group's columns with a scalar tail;
// the scalar path (T = double) is the reference the SIMD path is tested against.
//
// Per particle:
//  1. Jaumann rotation and elastic trial of the deviator (Eqs. 22, 35-37).
//  2. Energy predictor E* = E^n + deps : sigma^n / rho (App. A.2 step 7).
//  3. EOS at (rho^{n+1}, E*): pressure and c_K (Eqs. 8-12); intact c_p (Eq. 13). With a
//     porosity policy (kernels/porosity), first the compaction of the distension alpha, then
//     the matrix EOS at alpha rho and the bulk pressure p_s / alpha.
//  4. Plastic return of the strength model (App. B, Eqs. 4-6, 41-49), plastic strain and heat.
//  5. Artificial viscosity q on compression, with the longitudinal speed c_p of Eq. 13.
//  6. Damage: the policy evolves D from the intact stress (kernels/damage).
//  7. Effective stress sigma = (1-D) s - (p* + q) I, p* = (1-D) p in tension (Eq. 14), with the
//     damage-stress coupling of the material (DamageCoupling below).
//  8. Energy corrector E^{n+1} = E^n + deps : (sigma^n + sigma^{n+1})/2 / rho (A.2 step 7).
//  9. Sound speed for the time step (Eq. 34): Eq. 13 with the shear stiffness the next step's
//     stress will have ((1-D) G where Eq. 14 scales the deviator).
// With the material key shear_from_eos (strength::ElasticConstants::from_eos) G and K are the
// point's: scaled by m = rho c_K^2 / K at (rho^{n+1}, E*) of step 3, so the elastic trial of
// step 1 is made after the EOS; every use of G and K (trial, return, damage's E_Y, Eq. 13) takes
// m. With constant moduli m = 1 exactly and the arithmetic is that of the constants.
//
// Strength models whose yield surface already carries D (modified Lundborg Eq. 4, Lundborg /
// Collins Eqs. 47-49; they declare kDamageInYield) return a deviator that is the damaged rock's
// own: Eq. 14's (1 - D) is not applied to it again. Applied twice, fully damaged rock would have
// no shear strength at any pressure, where Eq. 4 leaves it the granular friction
// mu_d p / (1 + mu_d p / Ym) the paper describes (Sec. 3.1). Eq. 14 is Benz & Asphaug's (1994)
// coupling for a strength model that knows nothing of damage; Collins et al. (2004), whose damaged
// branch Eqs. 48-49 are, let damage act through the yield strength alone. The tensile pressure
// keeps Eq. 14's p* = (1 - D) p for every model (no yield surface caps the mean stress).

#include <cstddef>
#include <numbers>
#include <string_view>

#include "constitutive/artificial_viscosity.hpp"
#include "constitutive/simd.hpp"
#include "damage/damage_policy.hpp"
#include "porosity/porosity.hpp"
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
  // The increments: particle p's at deps[k][p - increments_begin] (a caller's chunk buffer,
  // include/shatter/material/material_model.hpp IncrementViews; 0 for store columns).
  const double* deps[6] = {};
  const double* dspin[3] = {};
  std::size_t increments_begin = 0;
  double* sdev[6] = {};  // undamaged deviator (damage on)
  double* plastic_strain = nullptr;
  double* heat = nullptr;
  // damage, eps_min, eps_max, n_flaws, weibull_m, n_active
  double* damage_state[6] = {};
  double* distension = nullptr;       // alpha = rho_s / rho (porosity on)
  double* compaction_heat = nullptr;  // booked compaction work, J/kg (porosity on)
  // r-z (issue 31): the points' radius x when each point is a ring about z, else null.
  const double* ring_radius = nullptr;
};

// How the damage D reaches the stress (issue 11; docs/fracture.md, "Damage-stress coupling").
// A material's damage.coupling key selects it (src/materials/damage_factory.cpp).
enum class DamageCoupling {
  // Eq. 14 with D^{n+1}: the stored undamaged deviator and the tensile pressure are scaled by
  // (1 - D) of the end of the step, so the stress drops as soon as D grows (Benz & Asphaug 1994
  // Eq. 13 read literally; shatter's behaviour before issue 11).
  total,
  // The paper's base code MPM3D-F90 (src/Constitution.f90: young_ = young_ * (1 - DMG), the
  // shear modulus G2/2 and the bulk 3K from it, and elastic_devi adds G2 (deps - deps_m) to the
  // stored deviator): each step's deviatoric increment is 2 (1 - D^n) G deps'. The borne
  // deviator (that of the stress columns) is not rescaled when D grows and is relieved only by
  // unloading or the plastic return (to the model's yield surface at D^n). The pressure is a
  // state function of the EOS and takes Eq. 14's p* = (1 - D^{n+1}) p in tension. The
  // undamaged deviator is still integrated (sdev) and is what the damage policy reads: Eq. 18's
  // (1 - D) divisor turns a stress scaled by (1 - D) back into the matrix strain, which the
  // borne stress of this form is not. Applied to the borne stress, the strain estimate grows
  // as D grows with nothing relieving it and every point runs away to D = 1 (100.0% failed in
  // all five 1.2 mm nominal runs; docs/validation-lab-impact.md).
  incremental,
  // Eq. 14 with D^n: the damage computed in a step reaches the stress in the next one, as the
  // MPM paper's Sec. 4.1.5 describes its code: "the damage is accumulated at the current time
  // step while the stress is not adjusted until the following time step".
  lagged,
};

// The default: Eq. 14 (Sec. 3.3) applied as Sec. 4.1.5 says the paper's code applies it, one
// step late. Eq. 14 alone does not say when D enters; Sec. 4.1.5 does, and the base code's
// incremental form is not in the paper's text (docs/fracture.md).
inline constexpr DamageCoupling kDefaultCoupling = DamageCoupling::lagged;

inline constexpr std::string_view coupling_name(DamageCoupling c) {
  return c == DamageCoupling::total         ? "total"
         : c == DamageCoupling::incremental ? "incremental"
                                            : "lagged";
}

// Strength models whose yield surface contains D (see the header comment).
template <class S>
concept DamageInYield = requires {
  requires S::kDamageInYield;
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

template <class Eos, class Strength, class Damage, class Porosity = porosity::NoPorosity>
class ComposedKernel {
 public:
  static constexpr bool kDamaged = Damage::kEnabled;

  ComposedKernel(Eos eos, Strength strength, Damage damage,
                 DamageCoupling coupling = kDefaultCoupling, Porosity porosity = {})
      : eos_(eos), strength_(strength), damage_(damage), coupling_(coupling), porosity_(porosity) {}

  const Eos& eos() const { return eos_; }
  const Porosity& porosity() const { return porosity_; }
  const Strength& strength() const { return strength_; }
  const Damage& damage() const { return damage_; }
  DamageCoupling coupling() const { return coupling_; }

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
      const auto e = initial_eos(c, p);  // first: it sets a new point's distension
      const double alpha = Porosity::kEnabled ? c.distension[p] : 1.0;
      double s[6];
      load_deviator<double>(c, p, s);
      if constexpr (!Damage::kEnabled) to_matrix(s, alpha);
      const double rho = c.rho[p];
      double D = simd::load_or<double>(ptr(c.damage_state[0], p), 0.0);
      if constexpr (Porosity::kEnabled) D = with_compaction(D, porosity_.compaction_damage(alpha));
      if constexpr (!Strength::kHasShear) {
        for (auto& x : s) x = 0.0;
      }
      if constexpr (Damage::kEnabled) {
        for (int k = 0; k < 6; ++k) c.sdev[k][p] = s[k];
      }
      const strength::PlasticState<double> ps{
          e.p, 0.0, simd::load_or<double>(ptr(c.heat, p), 0.0), D, rho, c.energy[p], 0.0};
      double sig[6];
      effective_stress(s, e.p, 0.0, D, deviator_factor(D) * porous_deviator_factor(alpha), sig);
      for (int k = 0; k < 6; ++k) c.stress[k][p] = sig[k];
      c.pressure[p] = e.p;
      const double m = strength_.elastic.modulus_scale(rho, e.c2);
      c.soundspeed[p] = longitudinal_speed(e.c2, rho, m, shear_fraction(D, e.p, ps));
    }
  }

  // Eq. 13: c_p = sqrt(4 f G/(3 rho) + c_K^2) with f the fraction of the shear stiffness G the
  // particle's stress update has (shear_fraction): 1 for intact material, (1 - D) where Eq. 14
  // scales the deviator. Fully damaged debris (D = 1) carries no shear wave; with the intact G
  // its shear term grows like 1/rho as it expands (39 km/s for basalt at rho = 20 kg/m^3) and
  // sets a needlessly short step. The bulk term stays whole: in compression Eq. 14 keeps p; in
  // tension p* = (1 - D) p would lower c_K too, and keeping the intact c_K there only errs on
  // the safe (shorter-step) side. m is the point's modulus scale (1, or rho c_K^2 / K with the
  // EOS-following moduli: then 4 G m / (3 rho) = c_K^2 2 (1 - 2 nu) / (1 + nu), and expanded
  // ejecta, whose c_K falls, no longer carry the P-wave speed of the solid's G at 1% of rho0).
  template <class T>
  T longitudinal_speed(const T& c2, const T& rho, const T& m, const T& shear = T(1.0)) const {
    return simd::vsqrt(c2 + (4.0 / 3.0) * strength_.elastic.G * shear * m / rho);
  }

  // Factor on the stored deviator in the effective stress (Eq. 14) at damage D: (1 - D), except
  // where the yield surface carries D (see the header comment): 1. (Incremental coupling uses
  // the borne deviator of the stress columns instead.)
  template <class T>
  T deviator_factor(const T& D) const {
    if (deviator_borne()) return T(1.0);
    return 1.0 - D;
  }

  // Fraction of G in the shear stiffness of the stress update at damage D and pressure p: the
  // deviator factor of Eq. 14, or (1 - D) of the incremental modulus; for a yield surface that
  // carries D, 0 where it gives no strength (Y(p, D) = 0: the return sets the deviator to zero
  // whatever the trial, so no shear wave propagates; fully damaged rock in tension), else that
  // fraction.
  template <class T>
  T shear_fraction(const T& D, const T& p, const strength::PlasticState<T>& ps) const {
    if constexpr (!Damage::kEnabled) {
      return T(1.0);
    } else {
      // (incremental: the increments' modulus is (1 - D) G whatever the yield surface)
      const T f = deviator_borne() && coupling_ != DamageCoupling::incremental ? T(1.0) : 1.0 - D;
      if constexpr (DamageInYield<Strength>) {
        return simd::vselect(strength_.yield_strength(p, D, ps) > 0.0, f, T(0.0));
      } else {
        return f;
      }
    }
  }

  // One particle's state through the step (the stages below fill it in order).
  template <class T>
  struct Point {
    T rho, rho_old, tr, e_old, e_trial, w_old, d_old;
    T alpha = T(1.0);  // distension (porosity stage; 1 without porosity)
    T a_old = T(1.0);  // the distension at the step's start
    T d_c = T(0.0);    // compaction damage D_c(alpha) (kernels/porosity; 0 when off)
    T m = T(1.0);      // modulus scale at (rho^{n+1}, E*) (ElasticConstants::modulus_scale)
    T de[6], w[3], sig_old[6];
    T s[6];                                                      // undamaged deviator
    T sb[6] = {T(0.0), T(0.0), T(0.0), T(0.0), T(0.0), T(0.0)};  // borne (incremental)
  };

  template <class T>
  void step(const ConstitutiveColumns& c, std::size_t p, const StepParams& sp) const {
    Point<T> pt;
    trial_stage(c, p, pt);
    const auto st_eos = eos_stage(c, p, pt);
    pt.m = strength_.elastic.modulus_scale(pt.rho, st_eos.c2);
    deviator_trial(pt);
    strength::PlasticState<T> ps = plastic_stage(c, p, pt, st_eos);
    const T pres = ps.p;

    // Eq. 13 of the intact material: the crack speed c_g = 0.4 c_p of Eq. 19 is that of a crack
    // tip running through the intact matrix between the cracks (BA95 Sec. 3), not a property of
    // the damaged particle as a whole; with (1 - D) G a particle's cracks would slow down as it
    // fails (to 0.4 c_K at D = 1), a feedback the Grady-Kipp model does not have.
    const T cp = longitudinal_speed(st_eos.c2, pt.rho, pt.m);

    // 5. Artificial viscosity with the longitudinal speed c_p of Eq. 13: the paper's Sec. 3.2
    // lists "the calculation of artificial viscosity used to capture shock fronts" among the uses
    // of c_p (and MPM3D-F90's bulkq multiplies the particle's c_p). The shear stiffness is the
    // one this step's stress update had (shear_fraction at D^n): the speed of the wave the
    // viscosity damps; for intact material that is Eq. 13 itself. Before issue 11 shatter used
    // the bulk c_K here (docs/validation-lab-impact.md measures the difference).
    const double inv_dt = sp.dt > 0.0 ? 1.0 / sp.dt : 0.0;
    const T c_visc =
        longitudinal_speed(st_eos.c2, pt.rho, pt.m, shear_fraction(pt.d_old, pres, ps));
    const auto av = artificial_viscosity(pt.tr, inv_dt, sp.cell_size, pt.rho, c_visc, sp.c_linear,
                                         sp.c_quadratic);

    const T dmg = damage_stage(c, p, pt, ps, cp, sp);
    stress_stage(c, p, pt, pres, av.q, dmg);
    if constexpr (Porosity::kEnabled) book_compaction(c, p, pt);

    // 9. Eq. 13 with the shear stiffness of the next step's stress update, which every coupling
    // takes at D^{n+1}, for the time step (Eq. 34): D never decreases, so that step's stress is
    // no stiffer than this.
    const T cp_damaged = Damage::kEnabled ? longitudinal_speed(st_eos.c2, pt.rho, pt.m,
                                                               shear_fraction(dmg, pres, ps))
                                          : cp;
    simd::store_col(c.pressure + p, pres);
    simd::store_col(c.soundspeed + p, cp_damaged + av.speed);
    simd::store_if(ptr(c.plastic_strain, p), ps.eps_p);
    simd::store_if(ptr(c.heat, p), ps.heat);
  }

 private:
  // Loads the point (and the borne deviator sb); 2. energy predictor. The elastic trial (1.)
  // follows the EOS stage (deviator_trial), where the point's moduli are known.
  template <class T>
  void trial_stage(const ConstitutiveColumns& c, std::size_t p, Point<T>& pt) const {
    using simd::load_col;
    pt.rho = load_col<T>(c.rho + p);
    pt.e_old = load_col<T>(c.energy + p);
    const std::size_t q = p - c.increments_begin;
    for (int k = 0; k < 6; ++k) pt.de[k] = load_col<T>(c.deps[k] + q);
    for (int k = 0; k < 3; ++k) pt.w[k] = load_col<T>(c.dspin[k] + q);
    for (int k = 0; k < 6; ++k) pt.sig_old[k] = load_col<T>(c.stress[k] + p);
    load_deviator<T>(c, p, pt.s);
    if constexpr (Porosity::kEnabled && !Damage::kEnabled) {
      to_matrix(pt.s, simd::load_col<T>(c.distension + p));
    }
    pt.d_old = simd::load_or<T>(ptr(c.damage_state[0], p), 0.0);

    // With incremental coupling the deviator the particle bears, sb (that of the stress
    // columns: q and p are isotropic), gets its own trial (deviator_trial); loaded here, with
    // the distension of the step's start.
    if constexpr (Strength::kHasShear) {
      if (incremental()) {
        const T m = (pt.sig_old[0] + pt.sig_old[1] + pt.sig_old[2]) * (1.0 / 3.0);
        for (int k = 0; k < 6; ++k) pt.sb[k] = k < 3 ? pt.sig_old[k] - m : pt.sig_old[k];
        if constexpr (Porosity::kEnabled) to_matrix(pt.sb, simd::load_col<T>(c.distension + p));
      }
    }

    // 2. Energy predictor. The engine sets rho^{n+1} = rho^n / (1 + tr deps), i.e. the volume
    // grows by tr(deps) V^n, so the work per unit mass is deps : sigma V^n / m = deps : sigma /
    // rho^n: with this density the energy change matches the engine's volume change exactly
    // (for a gas, dE = -p dV/m with no O(tr deps) bias). For a porous bulk this p dV work of
    // the bulk stress is also the work of compaction (kernels/porosity/porosity.hpp).
    pt.tr = pt.de[0] + pt.de[1] + pt.de[2];
    pt.rho_old = pt.rho * (1.0 + pt.tr);
    pt.w_old = double_contraction(pt.de, pt.sig_old);
    pt.e_trial = pt.e_old + pt.w_old / pt.rho_old;
  }

  // 1. Jaumann rotation + elastic trial (Eqs. 22, 35-37) with the point's shear modulus G m.
  // With incremental coupling sb's increment has the shear modulus (1 - D^n) G m (MPM3D-F90,
  // DamageCoupling::incremental); s stays the undamaged deviator the damage policy reads.
  template <class T>
  void deviator_trial(Point<T>& pt) const {
    if constexpr (Strength::kHasShear) {
      const T g = strength_.elastic.G * pt.m;
      strength::jaumann_trial(pt.s, pt.de, pt.w, g);
      if (incremental()) strength::jaumann_trial(pt.sb, pt.de, pt.w, g * (1.0 - pt.d_old));
    } else {
      (void)pt;
    }
  }

  // 3. EOS (Eqs. 8-12) at (rho^{n+1}, E*); with porosity, compaction of the distension first and
  // the matrix EOS at rho_s = alpha rho (kernels/porosity/porosity.hpp).
  template <class T>
  eos::EosPoint<T> eos_stage(const ConstitutiveColumns& c, std::size_t p, Point<T>& pt) const {
    if constexpr (Porosity::kEnabled) {
      const T a_old = simd::load_col<T>(c.distension + p);
      pt.alpha = porosity_.compact(eos_, pt.rho, pt.rho_old, pt.e_trial, a_old);
      simd::store_col(c.distension + p, pt.alpha);
      if constexpr (Damage::kEnabled) pt.d_c = porosity_.compaction_damage(pt.alpha);
      pt.a_old = a_old;
      return porosity_.bulk(eos_, pt.rho, pt.e_trial, pt.alpha);
    } else {
      (void)c;
      (void)p;
      return eos_.evaluate(pt.rho, pt.e_trial);
    }
  }

  // The compaction work of the step (kernels/porosity/porosity.hpp, compaction_work) with the
  // mean stress at the step's two ends, artificial viscosity and damage included: the stress
  // whose work the energy update (step 2 and the corrector) puts into E, so the booked heat is
  // the part of that work done on the pores. (Already inside E: booked, not added.)
  template <class T>
  void book_compaction(const ConstitutiveColumns& c, std::size_t p, const Point<T>& pt) const {
    using simd::load_col;
    const T p_old = -(pt.sig_old[0] + pt.sig_old[1] + pt.sig_old[2]) * (1.0 / 3.0);
    const T p_new = -(load_col<T>(c.stress[0] + p) + load_col<T>(c.stress[1] + p) +
                      load_col<T>(c.stress[2] + p)) *
                    (1.0 / 3.0);
    const T w = porosity_.compaction_work(p_old, p_new, pt.a_old, pt.alpha, pt.rho_old, pt.rho);
    simd::store_col(c.compaction_heat + p, load_col<T>(c.compaction_heat + p) + w);
  }

  // 4. Plastic return of the strength model (App. B).
  template <class T>
  strength::PlasticState<T> plastic_stage(const ConstitutiveColumns& c, std::size_t p, Point<T>& pt,
                                          const eos::EosPoint<T>& st_eos) const {
    strength::PlasticState<T> ps{st_eos.p,
                                 simd::load_or<T>(ptr(c.plastic_strain, p), 0.0),
                                 simd::load_or<T>(ptr(c.heat, p), 0.0),
                                 with_compaction(pt.d_old, pt.d_c),
                                 pt.rho,
                                 pt.e_trial,
                                 T(0.0),
                                 pt.m};
    if constexpr (Strength::kHasShear) {
      if (incremental()) {
        // The borne deviator returns to the same yield surface (at D^n); the pressure, plastic
        // strain and heat are those of the undamaged return below.
        auto pb = ps;
        strength_.return_map(pt.sb, pb);
      }
    }
    strength_.return_map(pt.s, ps);
    return ps;
  }

  // 6. Damage from the intact stress s - p I: the stress of the matrix at its full moduli, so
  // s / 2G is its strain, which is what Eq. 18 asks for (the policy rebuilds Eq. 14's stress
  // with D^n and divides by (1 - D) E, grady_kipp.hpp). That holds for a yield surface that
  // carries D too: its elastic modulus is never degraded, only its strength. Treating its
  // borne deviator as a (1 - D)-scaled stress (dividing it by 1 - D) makes the strain estimate
  // grow as D grows and runs away (modified Lundborg, Y0 = 60 MPa, 1.2 mm: 96.9% failed at
  // 100 us instead of 67%; docs/validation-lab-impact.md), as does Eq. 18 on the borne stress
  // of the incremental coupling (DamageCoupling::incremental).
  // The volume is that of the matrix, m / (alpha rho): a porous body's flaws are per unit
  // volume of solid (JBM08 Sec. 3.3); without porosity alpha = 1 and the division is not made.
  template <class T>
  T damage_stage(const ConstitutiveColumns& c, std::size_t p, const Point<T>& pt,
                 const strength::PlasticState<T>& ps, const T& cp, const StepParams& sp) const {
    if constexpr (Damage::kEnabled) {
      damage::DamageInput<T> in;
      for (int k = 0; k < 6; ++k) in.s[k] = pt.s[k];
      for (int k = 0; k < 3; ++k) in.s[k] = in.s[k] - ps.p;
      in.young = T(strength_.elastic.young) * pt.m;  // E_Y m: the point's Young's modulus
      in.soundspeed = cp;
      in.volume = simd::load_or<T>(ptr(c.mass, p), 0.0) / pt.rho;
      if constexpr (Porosity::kEnabled) in.volume = in.volume / pt.alpha;
      if (c.ring_radius != nullptr) {
        // r-z: the point is a ring V = 2 pi r A; its flaws are those of one 3-D point of its
        // cross-section's size, volume A^(3/2) (src/fracture/flaws.cpp), whose R_s Eq. 19 takes.
        const T r = simd::vmax(simd::load_or<T>(ptr(c.ring_radius, p), 0.0), T(1e-300));
        const T a = in.volume / (2.0 * std::numbers::pi * r);
        in.volume = a * simd::vsqrt(a);
      }
      in.dplastic = ps.deps_p;
      in.dt = sp.dt;
      damage::DamageState<T> ds;
      T* fields[6] = {&ds.damage,  &ds.eps_min,   &ds.eps_max,
                      &ds.n_flaws, &ds.weibull_m, &ds.n_active};
      for (int k = 0; k < 6; ++k) *fields[k] = simd::load_or<T>(ptr(c.damage_state[k], p), 0.0);
      const T dmg = damage_.evolve(in, ds);
      ds.damage = dmg;
      for (int k = 0; k < 6; ++k) simd::store_if(ptr(c.damage_state[k], p), *fields[k]);
      for (int k = 0; k < 6; ++k) simd::store_col(c.sdev[k] + p, pt.s[k]);
      return dmg;
    } else {
      (void)c, (void)p, (void)pt, (void)ps, (void)cp, (void)sp;
      return T(0.0);
    }
  }

  // 7. Effective stress (Eq. 14) with the viscous pressure; lagged coupling applies D^n, the
  // others D^{n+1}. 8. Energy corrector: midpoint stress sigma^{n+1/2} = (sigma^n + sigma^{n+1})/2.
  template <class T>
  void stress_stage(const ConstitutiveColumns& c, std::size_t p, const Point<T>& pt, const T& pres,
                    const T& q, const T& dmg) const {
    const T d_sig = with_compaction(
        Damage::kEnabled && coupling_ == DamageCoupling::lagged ? pt.d_old : dmg, pt.d_c);
    // the bulk deviator from the matrix's (kernels/porosity: S = S_s / alpha when on)
    const T f_por = porous_deviator_factor(pt.alpha);
    T sig[6];
    if (Strength::kHasShear && incremental()) {
      effective_stress(pt.sb, pres, q, d_sig, f_por, sig);
    } else {
      effective_stress(pt.s, pres, q, d_sig, deviator_factor(d_sig) * f_por, sig);
    }
    for (int k = 0; k < 6; ++k) simd::store_col(c.stress[k] + p, sig[k]);
    const T w_new = double_contraction(pt.de, sig);
    simd::store_col(c.energy + p, pt.e_old + 0.5 * (pt.w_old + w_new) / pt.rho_old);
  }

  bool incremental() const { return Damage::kEnabled && coupling_ == DamageCoupling::incremental; }

  // Porosity's degradation of the bulk (kernels/porosity/porosity.hpp): the factor on the matrix
  // deviator (1 / alpha or 1) and the damage D = min(1, D_t + D_c) (miluphcuda's damage_total).
  template <class T>
  T porous_deviator_factor(const T& alpha) const {
    if constexpr (Porosity::kEnabled) {
      return porosity_.deviator_factor(alpha);
    } else {
      (void)alpha;
      return T(1.0);
    }
  }
  // The matrix deviator of a bulk deviator that the stress columns hold at distension alpha:
  // s / factor(alpha) (an exact no-op when the scaling is off: a division by 1).
  template <class T>
  void to_matrix(T (&s)[6], const T& alpha) const {
    if constexpr (Porosity::kEnabled) {
      const T f = porosity_.deviator_factor(alpha);
      for (auto& x : s) x = x / f;
    } else {
      (void)s, (void)alpha;
    }
  }
  template <class T>
  static T with_compaction(const T& d, const T& d_c) {
    if constexpr (Porosity::kEnabled && Damage::kEnabled) {
      return simd::vmin(d + d_c, T(1.0));
    } else {
      (void)d_c;
      return d;
    }
  }
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

  // The stored deviator (sdev) is the one the particle bears: the yield surface carries D, and
  // Eq. 14's (1 - D) is not applied to it.
  bool deviator_borne() const { return DamageInYield<Strength>; }

  // Eq. 14: sigma = f s - p* I with f = deviator_factor(D) ((1 - D) or 1), p* = (1 - D) p in
  // tension, p otherwise; minus q I.
  template <class T>
  static void effective_stress(const T (&s)[6], const T& p, const T& q, const T& D, const T& f,
                               T (&sig)[6]) {
    const T one_d = 1.0 - D;
    const T p_eff = simd::vselect(p < 0.0, one_d * p, p) + q;
    for (int k = 0; k < 6; ++k) sig[k] = f * s[k];
    for (int k = 0; k < 3; ++k) sig[k] = sig[k] - p_eff;
  }

  // The EOS point of the stored state. A distension column that a new store zero-filled is
  // set to alpha0; one restored from a checkpoint (>= 1) is kept.
  eos::EosPoint<double> initial_eos(const ConstitutiveColumns& c, std::size_t p) const {
    if constexpr (Porosity::kEnabled) {
      if (!(c.distension[p] >= 1.0)) c.distension[p] = porosity_.alpha0();
      return porosity_.bulk(eos_, c.rho[p], c.energy[p], c.distension[p]);
    } else {
      return eos_.evaluate(c.rho[p], c.energy[p]);
    }
  }

  Eos eos_;
  Strength strength_;
  Damage damage_;
  DamageCoupling coupling_;
  Porosity porosity_;
};

}  // namespace shatter::constitutive
