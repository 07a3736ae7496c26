#pragma once
// Modified Lundborg model of the MPM paper (Sec. 3.1): one C1 yield surface
//   f = tau - [ (1-D) mu_i p / (1 + mu_i p/(Ym - Y0)) + (1-D) Y0 + D mu_d p / (1 + mu_d p/Ym) ]
//             * (1 - Q/Q_melt)                                                        (Eq. 4)
// with the non-associated potential psi = tau - q_psi p (Eq. 46) and the plastic corrector
//   dlambda = f(sigma*) / (G + K q_psi H),  p = p* + K q_psi dlambda,
//   tau = tau* - G dlambda,  s = (tau/tau*) s*                                        (Eq. 5a-d)
// where H = dY/dp. Eqs. 5a and 5b are solved together by Newton's method on
//   g(dl) = tau* - G dl - Y(p* + K q_psi dl) = 0,
// whose first iterate from dl = 0 is exactly Eq. 5a; the paper's "substitute and iterate".
// Plastic strain follows Eqs. 6a-6c and the heat dQ = sigma : deps_p (Eq. 40) accumulates into
// Q, which softens the surface through (1 - Q/Q_melt). Q^n (start of step) is used in Eq. 4, so
// the heat of this step softens the next one.
// Optional tension cut-off p_t <= 0 (material key tension_cutoff; absent = off, bitwise the
// return without it), as in lundborg.hpp (its header gives the sources): the corrector starts
// from p = max(p*, p_t) in place of p*, so below p_t the pressure is p_t and Eq. 4 is taken
// there (Eq. 5b adds nothing: dilatancy acts only for p > 0, and p_t <= 0).

#include <limits>

#include "strength/strength_common.hpp"

namespace shatter::strength {

struct ModifiedLundborg {
  static constexpr FieldSet kFields{Field::plastic_strain, Field::heat};
  static constexpr bool kHasShear = true;
  // Eq. 4 carries the damage: (1 - D) weighs the intact branch and D the damaged friction
  // branch, so the returned deviator is already the damaged rock's; the composed kernel does not
  // scale it by (1 - D) a second time (Eq. 14; kernels/constitutive/composed_kernel.hpp).
  static constexpr bool kDamageInYield = true;
  // Newton iterations of Eq. 5a/5b. g is convex and decreasing where Y is concave, so Newton from
  // dl = 0 converges monotonically and quadratically; 12 iterations reach round-off from any
  // start (tested), and the count is fixed so SIMD lanes and the scalar path agree exactly.
  static constexpr int kIterations = 12;

  ElasticConstants elastic{};
  double cohesion = 0.0;          // Y0 (Pa)
  double friction_intact = 0.0;   // mu_i
  double friction_damaged = 0.0;  // mu_d
  double strength_limit = 0.0;    // Ym (Pa)
  double dilatancy = 0.0;         // q_psi
  double melt_heat = 0.0;         // Q_melt (J/kg); 0 = no thermal softening
  // p_t (Pa, <= 0); -infinity = no cut-off (the default)
  double tension_cutoff = -std::numeric_limits<double>::infinity();

  bool has_tension_cutoff() const {
    return tension_cutoff > -std::numeric_limits<double>::infinity();
  }

  // Below p_t = -Y0 (Ym - Y0)/(mu_i Ym) the intact term of Eq. 4 would go negative (and reach a
  // pole); it is held at zero there. The damaged term is held at zero for p < 0 (no cohesion).
  double intact_tension() const {
    return -cohesion * (strength_limit - cohesion) / (friction_intact * strength_limit);
  }

  template <class T>
  T melt_factor(const T& heat) const {
    if (melt_heat <= 0.0) return T(1.0);
    return vmin(vmax(1.0 - heat / melt_heat, T(0.0)), T(1.0));
  }

  // Yield strength Y(p) of Eq. 4 (the bracket times the melt factor) and H = dY/dp (Eq. 5a).
  template <class T>
  void yield(const T& p, const T& damage, const T& melt, T& y, T& h) const {
    const double ci = friction_intact / (strength_limit - cohesion);
    const double cd = friction_damaged / strength_limit;
    const T pi = vmax(p, T(intact_tension()));
    const T pd = vmax(p, T(0.0));
    const T di = 1.0 + ci * pi;
    const T dd = 1.0 + cd * pd;
    const T yi = friction_intact * pi / di + cohesion;
    const T yd = friction_damaged * pd / dd;
    const T hi = vselect(p > intact_tension(), friction_intact / (di * di), T(0.0));
    const T hd = vselect(p > 0.0, friction_damaged / (dd * dd), T(0.0));
    const T one_d = 1.0 - damage;
    y = (one_d * yi + damage * yd) * melt;
    h = (one_d * hi + damage * hd) * melt;
  }

  // Y of Eq. 4 at pressure p and damage D with the particle's plastic heat (melt factor).
  template <class T>
  T yield_strength(const T& p, const T& damage, const PlasticState<T>& st) const {
    T y, h;
    yield(p, damage, melt_factor(st.heat), y, h);
    return y;
  }

  template <class T>
  void return_map(T (&s)[6], PlasticState<T>& st) const {
    const T G = elastic.G * st.modulus;  // the point's shear modulus (PlasticState::modulus)
    const T tau_trial = vsqrt(j2(s));
    const T p_star = st.p;
    // The corrector's starting pressure: p* clipped at the tension cut-off when there is one.
    const T p_trial = has_tension_cutoff() ? vmax(p_star, T(tension_cutoff)) : p_star;
    // Dilatancy is shear-induced bulking against a confining pressure, so Eq. 5b acts only for
    // p* > 0. Without confinement there is nothing to bulk against, and a fully damaged particle
    // (Y = 0 in tension) would turn all of each step's shear into K q_psi dlambda of compression:
    // free-flying debris at 1% of rho0 reached +1 GPa, expanded under it to E = -4e7 J/kg and
    // shot out at 9 km/s (lab impact, Y0 = 10 MPa, 97 us; docs/materials.md).
    const T kq = vselect(p_trial > 0.0, T(elastic.K * dilatancy) * st.modulus, T(0.0));
    const T melt = melt_factor(st.heat);
    const T dl_max = tau_trial / G;  // tau >= 0 bounds the multiplier

    T y, h;
    yield(p_trial, st.damage, melt, y, h);
    const auto plastic = tau_trial > y;  // f(sigma*) > 0
    T dl(0.0);
    for (int it = 0; it < kIterations; ++it) {
      yield(p_trial + kq * dl, st.damage, melt, y, h);
      const T g = tau_trial - G * dl - y;
      dl = vmin(vmax(dl + g / (G + kq * h), T(0.0)), dl_max);  // Eq. 5a, Newton form
    }
    dl = vselect(plastic, dl, T(0.0));

    const T p = p_trial + kq * dl;                    // Eq. 5b
    const T tau = tau_trial - G * dl;                 // Eq. 5c
    scale(s, tau / vmax(tau_trial, T(kTinyStress)));  // Eq. 5d
    st.p = p;
    // Eqs. 6a-6c and 40 through the common bookkeeping: with tau* - tau = G dl and
    // p - p* = K q_psi dl it gives deps_bar = dl sqrt(1/3 + 2 q_psi^2 / 9) (Eq. 6c) and
    // dQ = dl (tau - q_psi p).
    book_plastic_work(tau_trial, tau, p_star, p, elastic, st);
  }
};

}  // namespace shatter::strength
