#pragma once
// Tillotson equation of state with cold expansion, mixing region and low-energy vapour expansion
// (MPM paper Sec. 3.2, Eqs. 8-12; Brundage 2013). Header-only kernel: T is double or
// xsimd::batch<double>; the branches are evaluated and the region chosen with select, so the
// SIMD lanes never diverge (the hot and mixing branches only in a batch with a lane there).

#include <cstdint>

#include "eos/eos_common.hpp"

namespace shatter::eos {

struct TillotsonParams {
  double rho0 = 0.0;  // reference density (kg/m^3)
  double A = 0.0;     // Pa
  double B = 0.0;     // Pa
  double a = 0.0;     // -
  double b = 0.0;     // -
  double E0 = 0.0;    // J/kg
  double Eiv = 0.0;   // J/kg, incipient vaporisation
  double Ecv = 0.0;   // J/kg, complete vaporisation
  // kg/m^3, incipient-vaporisation density; 0 = the classic formulation without the vapour
  // branch of Eq. 11 (Benz & Asphaug 1999), for materials whose rho_iv is not published.
  double rho_iv = 0.0;
  double alpha = 0.0;  // -
  double beta = 0.0;   // -
};

// The regions of Fig. 3a (MPM paper).
enum class TillotsonRegion : std::uint8_t {
  compressed,        // rho >= rho0, Eq. 8
  cold_expanded,     // rho_iv <= rho < rho0, E <= Eiv, Eq. 8
  mixed,             // rho_iv <= rho < rho0, Eiv < E < Ecv, Eq. 10
  hot_expanded,      // rho < rho0, E >= Ecv, Eq. 9
  vapour_expansion,  // rho < rho_iv, E < Ecv, Eq. 11
};

inline const char* name_of(TillotsonRegion r) {
  constexpr const char* kNames[] = {"compressed", "cold_expanded", "mixed", "hot_expanded",
                                    "vapour_expansion"};  // in the enum's order
  const auto i = static_cast<std::size_t>(r);
  return i < std::size(kNames) ? kNames[i] : "?";
}

class Tillotson {
 public:
  explicit Tillotson(const TillotsonParams& q) : q_(q) {
    const double mu_iv = q.rho_iv / q.rho0 - 1.0;
    floor_slope_ = q.rho_iv > 0.0 ? q.A * mu_iv / q.rho_iv : 0.0;
    c2_floor_ = kSoundFloor * kSoundFloor * q.A / q.rho0;
  }

  const TillotsonParams& params() const { return q_; }
  double reference_density() const { return q_.rho0; }

  // Region of a state, after the same clamps as evaluate() (E < 0 is treated as E = 0).
  TillotsonRegion region(double rho, double E) const {
    E = E < 0.0 ? 0.0 : E;
    if (rho >= q_.rho0) return TillotsonRegion::compressed;
    if (E >= q_.Ecv) return TillotsonRegion::hot_expanded;
    if (rho < q_.rho_iv) return TillotsonRegion::vapour_expansion;
    return E <= q_.Eiv ? TillotsonRegion::cold_expanded : TillotsonRegion::mixed;
  }

  // Pressure floor of the low-density vapour branch: p >= A mu_iv rho / rho_iv for rho < rho_iv.
  // Eq. 11 keeps the A mu term, so a cold state at rho -> 0 would hold a tension of -A (-26.7 GPa
  // for basalt): material that has expanded past incipient vaporisation cannot. The floor equals
  // Eq. 11 at rho_iv (E = 0), so p stays continuous there, and falls linearly to 0 at rho = 0.
  double pressure_floor(double rho) const { return floor_slope_ * rho; }

  // kAllBranches = true evaluates Eqs. 9-10 in every batch (the reference of the tests).
  template <class T, bool kAllBranches = false>
  EosPoint<T> evaluate(const T& rho_in, const T& E_in) const {
    using simd::vexp;
    using simd::vmax;
    const double rho0 = q_.rho0;
    // Negative specific energy is below the cold curve E = 0 that Tillotson is referred to, and
    // would make omega = E/(E0 eta^2) + 1 vanish; the EOS sees E >= 0 (the energy column keeps
    // its value, so energy accounting is untouched).
    const T rho = vmax(rho_in, T(kMinDensityFraction * rho0));
    const T E = vmax(E_in, T(0.0));

    const T eta = rho / rho0;
    const T mu = eta - 1.0;
    const T omega = E / (q_.E0 * eta * eta) + 1.0;
    const T b_om = q_.b / omega;
    // d(b/omega)-type term: omega - 1 = E rho0^2 / (E0 rho^2), so both partials of
    // b rho E / omega reduce to b (omega - 1) / omega^2 (valid also at E = 0).
    const T b_om2 = q_.b * (omega - 1.0) / (omega * omega);

    // Eq. 8 (compressed and cold expanded).
    const T gam = q_.a + b_om;
    const T p1 = gam * rho * E + q_.A * mu + q_.B * mu * mu;
    const T p1_r = gam * E + 2.0 * E * b_om2 + (q_.A + 2.0 * q_.B * mu) / rho0;
    const T p1_e = gam * rho - rho * b_om2;
    const Branch<T> cold_branch{p1, p1_r, p1_e};

    // Eq. 11 (low-energy vapour expansion) is Eq. 8 without B mu^2.
    const T p4 = p1 - q_.B * mu * mu;
    const T p4_r = p1_r - 2.0 * q_.B * mu / rho0;
    const T p4_e = p1_e;

    const auto compressed = rho >= rho0;
    const auto hot = E >= q_.Ecv;
    const auto vapour = rho < q_.rho_iv;
    const auto cold = E <= q_.Eiv;

    // Eqs. 9 and 10 (two exp and seven divisions) only where a lane of the batch is in the hot
    // or the mixing region; elsewhere no lane selects them below, and every lane keeps the bits
    // it would have with them (the branches are selected lane by lane, never mixed).
    Branch<T> hot_branch = cold_branch, mixed_branch = cold_branch;
    if (kAllBranches || simd::any(!compressed && (hot || !(vapour || cold)))) {
      const T nu = rho0 / rho - 1.0;
      // Eq. 9 (hot expanded): p = a rho E + [b rho E / omega + A mu e^{-beta nu}] e^{-alpha nu^2}.
      const T ea = vexp(-q_.alpha * nu * nu);
      const T eb = vexp(-q_.beta * nu);
      const T x = b_om * rho * E;
      const T x_r = E * b_om + 2.0 * E * b_om2;
      const T x_e = rho * b_om - rho * b_om2;
      const T y = q_.A * mu * eb;
      const T drho_nu = rho0 / (rho * rho);  // -d(nu)/d(rho)
      const T y_r = q_.A * eb * (1.0 / rho0 + mu * q_.beta * drho_nu);
      const T p2 = q_.a * rho * E + (x + y) * ea;
      const T p2_r = q_.a * E + (x_r + y_r) * ea + (x + y) * ea * (2.0 * q_.alpha * nu * drho_nu);
      const T p2_e = q_.a * rho + x_e * ea;

      // Eq. 10 (mixing): linear in E between the Eq. 8 and Eq. 9 surfaces.
      const double dE = q_.Ecv - q_.Eiv;
      const T wh = (E - q_.Eiv) / dE;  // weight of the hot branch
      const T wc = (q_.Ecv - E) / dE;
      const T p3 = p2 * wh + p1 * wc;
      const T p3_r = p2_r * wh + p1_r * wc;
      const T p3_e = p2_e * wh + p1_e * wc + (p2 - p1) / dE;
      hot_branch = {p2, p2_r, p2_e};
      mixed_branch = {p3, p3_r, p3_e};
    }

    // Expanded, rho >= rho_iv: cold (Eq. 8), mixed (Eq. 10).
    Branch<T> out = pick(cold, cold_branch, mixed_branch);
    // Expanded below rho_iv: Eq. 11 with the documented floor.
    const T floor = floor_slope_ * rho;
    const Branch<T> vapour_branch =
        pick(p4 < floor, Branch<T>{floor, T(floor_slope_), T(0.0)}, Branch<T>{p4, p4_r, p4_e});
    out = pick(vapour, vapour_branch, out);
    // Hot expanded (Eq. 9) overrides both, then compression (Eq. 8) overrides everything.
    out = pick(hot, hot_branch, out);
    out = pick(compressed, cold_branch, out);

    return {out.p, vmax(isentropic_c2(rho, out.p, out.p_r, out.p_e), T(c2_floor_))};
  }

  // Reference bulk sound speed squared A / rho0 (the floor is a fraction of it).
  double reference_c2() const { return q_.A / q_.rho0; }

 private:
  // The pressure of one branch of Fig. 3a and its partials dp/drho, dp/dE.
  template <class T>
  struct Branch {
    T p, p_r, p_e;
  };
  // Lane by lane: a where the region mask m holds, else b.
  template <class M, class T>
  static Branch<T> pick(const M& m, const Branch<T>& a, const Branch<T>& b) {
    return {simd::vselect(m, a.p, b.p), simd::vselect(m, a.p_r, b.p_r),
            simd::vselect(m, a.p_e, b.p_e)};
  }

  TillotsonParams q_;
  double floor_slope_ = 0.0;
  double c2_floor_ = 0.0;
};

}  // namespace shatter::eos
