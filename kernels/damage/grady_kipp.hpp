#pragma once
// Grady–Kipp damage with explicit flaws (BA95 Sec. 3 and 4.3; MPM paper Sec. 3.3, Eqs. 17–19).
// The flaws of each particle (eps_min, eps_max, n_f, m_p) come from
// shatter/fracture/flaws.hpp; this policy turns the intact stress into damage growth.

#include <numbers>

#include <xsimd/xsimd.hpp>

#include "damage/damage_policy.hpp"
#include "damage/lanes.hpp"
#include "damage/principal.hpp"

namespace shatter::damage {

// Options of Eq. 19. Defaults follow the MPM paper and BA95; see docs/fracture.md for why.
struct GradyKippParams {
  // c_g = crack_speed_factor * c_p (BA95 Sec. 3, after Lawn & Wilshaw 1975).
  double crack_speed_factor = 0.4;
  // R_s of Eq. 19 in metres. 0 (default) = radius of the sphere with the particle's current
  // volume, (3 V / 4 pi)^(1/3): BA95 Eq. 14 defines R_s through V = 4/3 pi R_s^3, the volume a
  // crack must cross to damage the whole particle.
  double rs = 0.0;
  // c_p used for c_g in m/s. 0 (default) = the particle's current longitudinal sound speed
  // (MPM paper Sec. 3.2: the updated c_p of Eq. 13 enters Eq. 19); > 0 = a fixed intact value.
  double intact_soundspeed = 0.0;
  // Lower bound of (1 - D) in Eq. 18, so that a fully damaged particle yields a finite (huge)
  // strain instead of inf/NaN; any tension then activates every flaw, which is the limit.
  double min_intact_fraction = 1.0e-12;
};

// dD^(1/3)/dt = n_act c_g / R_s (MPM paper Eq. 19) with n_act = (eps_eff / eps_min)^m_p (Eq. 17)
// and eps_eff = sigma_max / ((1 - D) E) (Eq. 18) with sigma the damaged stress of Eq. 14;
// D <= (n_act / n_f)^(1/3) (BA95 Eq. 22).
struct GradyKipp {
  static constexpr FieldSet kFields{Field::damage,  Field::eps_min,   Field::eps_max,
                                    Field::n_flaws, Field::weibull_m, Field::n_active};
  static constexpr bool kEnabled = true;

  GradyKippParams params;

  template <class T>
  T evolve(const DamageInput<T>& in, DamageState<T>& st) const {
    const Matrix<T> m = matrix(in, st.damage);
    if (!may_activate(in, st, m)) {
      // No lane reaches its weakest flaw: n_act = 0 zeroes Eq. 19's increment and BA95 Eq. 22's
      // cap, so the full path below would keep D and store n_act = 0; done here without the
      // Jacobi sweeps and the exp, log and cbrt (~10 % of a laboratory impact's step).
      st.n_active = T(0.0);
      return st.damage;
    }
    return evolve_full(in, st, m);
  }

  // Eq. 18 reads sigma_max of the damaged stress sigma of Eq. 14 and divides by (1 - D) to get
  // the strain of the intact matrix that bears it (MPM paper Sec. 5.1). in.s is the intact
  // stress, so sigma is rebuilt: sigma = (1 - D) s' - p* I, p* = (1 - D) p in tension.
  // Dividing the intact stress by (1 - D) a second time would amplify the strain by 1/(1 - D)
  // and, with m_p ~ 40, drive any damaged particle in tension to D = 1 in one step.
  template <class T>
  struct Matrix {
    T intact;    // 1 - D, bounded below
    T pressure;  // of the intact stress
    T p_star;    // p*: the part of the pressure the damaged particle bears
  };
  template <class T>
  Matrix<T> matrix(const DamageInput<T>& in, const T& damage) const {
    const T intact = xsimd::max(T(1.0) - damage, T(params.min_intact_fraction));
    const T pressure = (in.s[0] + in.s[1] + in.s[2]) * T(-1.0 / 3.0);
    return {intact, pressure, simd::vselect(pressure < T(0.0), intact * pressure, pressure)};
  }
  // Eq. 18's strain for `largest`, the largest principal value of the intact stress
  // s (-p I shifts all principal values alike, so the largest of sigma follows from that of s).
  template <class T>
  T strain(const DamageInput<T>& in, const Matrix<T>& m, const T& largest) const {
    const T sigma_max = m.intact * (largest + m.pressure) - m.p_star;
    return xsimd::max(sigma_max, T(0.0)) / (m.intact * in.young);
  }

  // Whether any lane may reach its weakest flaw's threshold. An upper bound of Eq. 18's strain
  // from Gershgorin's bound on the largest principal value of s (max over rows of s_ii + the
  // row's |s_ij|, j != i), widened by 1e-6 of the tensor's absolute sum: far above the Jacobi
  // sweeps' round-off (7 eps ||s||, principal.hpp) and the few roundings after it, so that a
  // batch declared inactive here is one the full path finds inactive in every lane.
  template <class T>
  bool may_activate(const DamageInput<T>& in, const DamageState<T>& st, const Matrix<T>& m) const {
    const Gershgorin<T> g = gershgorin(in);
    const T eps_hi = strain(in, m, g.rows + T(1.0e-6) * g.size);
    return simd::any((eps_hi >= st.eps_min) && (st.eps_min > T(0.0)));
  }
  // Gershgorin's bound on the largest principal value of s and the tensor's absolute sum.
  template <class T>
  struct Gershgorin {
    T rows, size;
  };
  template <class T>
  static Gershgorin<T> gershgorin(const DamageInput<T>& in) {
    const T a3 = simd::vabs(in.s[3]), a4 = simd::vabs(in.s[4]), a5 = simd::vabs(in.s[5]);
    const T rows = xsimd::max(in.s[0] + a3 + a5, xsimd::max(in.s[1] + a3 + a4, in.s[2] + a4 + a5));
    const T size =
        simd::vabs(in.s[0]) + simd::vabs(in.s[1]) + simd::vabs(in.s[2]) + T(2.0) * (a3 + a4 + a5);
    return {rows, size};
  }

  // Eq. 17: n_act = min((eps_eff / eps_min)^m_p, n_f) in the active lanes, 0 elsewhere; with no
  // lane active the exp and log are not evaluated (kAllWork = false): the select gives +0 in
  // every lane whatever they return.
  template <class T, bool kAllWork, class Mask>
  static T active_flaws(const T& eps_eff, const DamageState<T>& st, const Mask& active) {
    if (!kAllWork && !simd::any(active)) return T(0.0);
    const T ratio = xsimd::max(eps_eff / simd::vselect(active, st.eps_min, T(1.0)), T(1.0));
    const T n_weibull = xsimd::exp(st.weibull_m * lanes::log(ratio));
    return simd::vselect(active, xsimd::min(n_weibull, st.n_flaws), T(0.0));
  }

  // Whether Eq. 19 and BA95 Eq. 22 leave every lane's D where
  // max(D^n, min(q, 1)), q = n_act / max(n_f, 1), puts it: where D^n >= 1, d_new =
  // max(D^n, min(..., 1)) is D^n whatever the increment (xsimd's min returns its second
  // operand, 1, for a NaN first one; the scalar min keeps the NaN, which max then drops), and so
  // is max(D^n, min(q, 1)); where n_act = 0 and D^n >= 0, the cap cbrt(q) is q (cbrt(+-0) =
  // +-0) and, the root being >= 0 or NaN, min(root^3, q) is q in the lanes (the scalar path:
  // q, or a zero or NaN that max(D^n, .) drops as it drops q), so d_new = max(D^n, min(q, 1)).
  // (n_f is not NaN there: the scalar max(n_f, 1) would keep it, and q with it.)
  template <class T>
  static bool settled(const T& d_old, const T& n_act, const T& n_flaws) {
    const auto idle = (n_act == 0.0) && (d_old >= 0.0) && !xsimd::isnan(n_flaws);
    return !simd::any(!((d_old >= 1.0) || idle));
  }
  // D where settled() holds: max(D^n, min(q, 1)), q = n_act / max(n_f, 1).
  template <class T>
  static T settled_damage(const T& d_old, const T& n_act, const T& n_flaws) {
    return xsimd::max(d_old, xsimd::min(n_act / xsimd::max(n_flaws, T(1.0)), T(1.0)));
  }

  // Whether bounds of the largest principal value decide every lane without the Jacobi sweeps;
  // then st holds what evolve_full would give, bit for bit. Bounds: lo = max_i s_ii (Rayleigh)
  // and Gershgorin's hi (may_activate), each widened by 1e-6 of the tensor's absolute sum,
  // far beyond the sweeps' round-off (7 eps ||s||); Eq. 18's strain is non-decreasing in the
  // principal value under rounding (each operation is), so eps(lo) <= eps_eff <= eps(hi). A lane
  // is idle where eps(hi) < eps_min or eps_min <= 0 (n_act = 0, Eq. 17), saturated where
  // eps(lo) >= eps_min > 0, m_p > 0 and (eps(lo) / eps_min)^m_p >= n_f (1 + 1e-6): the full
  // path's (eps_eff / eps_min)^m_p is then >= n_f (exp and log err by ulps, not 1e-6), and
  // n_act = min(., n_f) = n_f. Decided: idle lanes with D^n >= 0 (settled, below) and fully
  // damaged lanes either idle or saturated, whose D stays (settled). Where a fully damaged batch
  // is in tension well beyond its flaws' thresholds, or in compression, no sweep is made.
  template <class T>
  bool decided_by_bounds(const DamageInput<T>& in, DamageState<T>& st, const Matrix<T>& m) const {
    const Gershgorin<T> g = gershgorin(in);
    const T diag = xsimd::max(in.s[0], xsimd::max(in.s[1], in.s[2]));
    const T eps_hi = strain(in, m, g.rows + T(1.0e-6) * g.size);
    const T eps_lo = strain(in, m, diag - T(1.0e-6) * g.size);
    const T d_old = st.damage;
    const auto armed = st.eps_min > 0.0;
    const auto sane = in.young > 0.0;  // (the strain's monotony: E_Y > 0)
    const auto idle = sane && (!armed || (eps_hi < st.eps_min));
    const auto failed = d_old >= 1.0;
    const auto may_saturate = sane && armed && (eps_lo >= st.eps_min) && (st.weibull_m > 0.0);
    const auto idle_ok = idle && (d_old >= 0.0) && !xsimd::isnan(st.n_flaws);
    if (simd::any(!((failed && (idle || may_saturate)) || idle_ok))) return false;
    const T n_lo = xsimd::exp(st.weibull_m * lanes::log(eps_lo / st.eps_min));
    const auto saturated = may_saturate && (n_lo >= st.n_flaws * (1.0 + 1.0e-6));
    if (simd::any(!((failed && (idle || saturated)) || idle_ok))) return false;
    // idle and saturated exclude each other (eps(lo) <= eps(hi)).
    st.n_active = simd::vselect(saturated, st.n_flaws, T(0.0));
    st.damage = settled_damage(d_old, st.n_active, st.n_flaws);
    return true;
  }

  // Eqs. 17-19 and BA95 Eq. 22 in every lane; m = matrix(in, st.damage). kAllWork = true
  // evaluates every term in every batch (the reference of the tests; the same bits).
  template <class T, bool kAllWork = false>
  T evolve_full(const DamageInput<T>& in, DamageState<T>& st, const Matrix<T>& m) const {
    if (!kAllWork && decided_by_bounds(in, st, m)) return st.damage;
    const T d_old = st.damage;
    const T eps_eff = strain(in, m, principal_values<T, kAllWork>(in.s).s1);
    // Eq. 17; no flaw is active below the weakest threshold (BA95 Sec. 4.3), and at most the
    // n_f flaws the particle holds can be.
    const auto active = (eps_eff >= st.eps_min) && (st.eps_min > T(0.0));
    const T n_act = active_flaws<T, kAllWork>(eps_eff, st, active);
    st.n_active = n_act;
    if (!kAllWork && settled(d_old, n_act, st.n_flaws)) {
      // Every lane fully damaged or without an active flaw: Eq. 19's increment cannot move D
      // (below), so the three cbrt are not evaluated. Same bits.
      st.damage = settled_damage(d_old, n_act, st.n_flaws);
      return st.damage;
    }
    // Eq. 19 integrated over dt in D^(1/3).
    const T radius =
        params.rs > 0.0 ? T(params.rs) : lanes::cbrt(in.volume * (3.0 / (4.0 * std::numbers::pi)));
    const T cp = params.intact_soundspeed > 0.0 ? T(params.intact_soundspeed) : in.soundspeed;
    const T root = lanes::cbrt(d_old) + n_act * (params.crack_speed_factor * in.dt) * cp / radius;
    // BA95 Eq. 22 caps D by the fraction of active flaws; damage never heals.
    const T cap = lanes::cbrt(n_act / xsimd::max(st.n_flaws, T(1.0)));
    const T d_new = xsimd::max(d_old, xsimd::min(xsimd::min(root * root * root, cap), T(1.0)));
    st.damage = d_new;
    return d_new;
  }
};

}  // namespace shatter::damage
