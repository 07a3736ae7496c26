// Material probe (probe.hpp): EOS state and principal Hugoniot.

#include "shatter/material/probe.hpp"

#include <cmath>
#include <ostream>
#include <stdexcept>
#include <type_traits>
#include <variant>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "materials/model_factory.hpp"

namespace shatter {

namespace {

struct Eval {
  materials::AnyEos eos;
  strength::ElasticConstants elastic{};  // G = 0 for hydro

  eos::EosPoint<double> operator()(double rho, double e) const {
    return std::visit([&](const auto& m) { return m.evaluate(rho, e); }, eos);
  }
};

Eval make_eval(const MaterialSpec& spec) {
  validate(spec);
  const auto s = materials::make_strength(spec);
  const auto el = std::visit([](const auto& m) { return m.elastic; }, s);
  return {materials::make_eos(spec), el};
}

double reference_density(const Eval& ev) {
  return std::visit([](const auto& m) { return m.reference_density(); }, ev.eos);
}

}  // namespace

EosSample probe_eos(const MaterialSpec& spec, double rho, double energy) {
  const Eval ev = make_eval(spec);
  const auto pt = ev(rho, energy);
  EosSample out;
  out.rho = rho;
  out.energy = energy;
  out.pressure = pt.p;
  out.bulk_speed = std::sqrt(pt.c2);
  // Eq. 13 with the point's G (constant, or following the EOS: ElasticConstants::modulus_scale)
  const double g = ev.elastic.G * ev.elastic.modulus_scale(rho, pt.c2);
  out.soundspeed = std::sqrt(pt.c2 + 4.0 * g / (3.0 * rho));
  if (const auto* t = std::get_if<eos::Tillotson>(&ev.eos)) {
    out.region = eos::name_of(t->region(rho, energy));
  } else {
    out.region = spec.eos;
  }
  return out;
}

namespace {

// Solves the jump conditions for one up > 0 in the compression x = up / Us = 1 - rho_ref/rho:
// mass and energy jumps fix rho(x) and E(x) exactly; the momentum jump is the root of
//   F(x) = p_EOS(rho(x), E(x)) - p_ref - rho_ref up^2 / x,
// which tends to -inf as x -> 0 (a weak shock runs at infinite speed) and is positive as x -> 1
// for any EOS that stiffens under compression. The first sign change on a fine grid is refined by
// bisection down to adjacent doubles, so the row satisfies the jumps to round-off.
HugoniotRow solve_row(const Eval& ev, double up, double rho0, double e0, double p0) {
  const auto state = [&](double x, HugoniotRow& r) {
    r.up = up;
    r.us = up / x;
    r.rho = rho0 / (1.0 - x);
    r.energy = e0 + p0 * x / rho0 + 0.5 * up * up;  // (p + p0)/2 (1/rho0 - 1/rho), momentum used
    r.p = ev(r.rho, r.energy).p;
    return r.p - p0 - rho0 * up * up / x;
  };
  HugoniotRow r;
  constexpr int kGrid = 400;
  double lo = 0.0, hi = 0.0;
  bool found = false;
  double x_prev = 1e-9;
  double f_prev = state(x_prev, r);
  for (int k = 1; k <= kGrid && !found; ++k) {
    // Geometric up to x = 0.1, then linear to 0.999: weak shocks need small x, strong ones
    // large.
    const double x = k <= kGrid / 2 ? 1e-9 * std::pow(1e8, static_cast<double>(k) / (kGrid / 2))
                                    : 0.1 + 0.899 * (k - kGrid / 2) / (kGrid / 2.0);
    const double f = state(x, r);
    if (f_prev < 0.0 && f >= 0.0) {
      lo = x_prev;
      hi = x;
      found = true;
    }
    x_prev = x;
    f_prev = f;
  }
  if (!found) {
    throw std::runtime_error(
        fmt::format("hugoniot: no shocked state for up = {} m/s (the EOS does not stiffen enough "
                    "under compression up to rho/rho_ref = 1000)",
                    up));
  }
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    (state(mid, r) < 0.0 ? lo : hi) = mid;
  }
  state(hi, r);
  return r;
}

}  // namespace

std::vector<HugoniotRow> hugoniot(const MaterialSpec& spec, std::span<const double> up,
                                  HugoniotReference ref) {
  const Eval ev = make_eval(spec);
  const double rho0 = ref.rho > 0.0 ? ref.rho : reference_density(ev);
  const double e0 = ref.energy;
  const auto p_ref = ev(rho0, e0);
  std::vector<HugoniotRow> rows;
  rows.reserve(up.size());
  for (double u : up) {
    if (!(u >= 0.0) || !std::isfinite(u)) {
      throw std::invalid_argument(fmt::format("hugoniot: particle speed {} must be >= 0", u));
    }
    if (u == 0.0) {
      rows.push_back({0.0, std::sqrt(p_ref.c2), p_ref.p, rho0, e0});
    } else {
      rows.push_back(solve_row(ev, u, rho0, e0, p_ref.p));
    }
  }
  return rows;
}

std::vector<HugoniotRow> hugoniot(const MaterialSpec& spec, double up_max, int n,
                                  HugoniotReference ref) {
  if (n < 2) throw std::invalid_argument("hugoniot: need at least 2 points");
  std::vector<double> up(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) up[static_cast<std::size_t>(k)] = up_max * k / (n - 1);
  return hugoniot(spec, up, ref);
}

void write_hugoniot_csv(std::ostream& out, std::span<const HugoniotRow> rows) {
  out << "up_m_per_s,us_m_per_s,p_Pa,rho_kg_per_m3,energy_J_per_kg\n";
  for (const auto& r : rows) {
    fmt::print(out, "{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}\n", r.up, r.us, r.p, r.rho, r.energy);
  }
}

void write_hugoniot_table(std::ostream& out, std::span<const HugoniotRow> rows) {
  fmt::print(out, "{:>12} {:>12} {:>14} {:>14} {:>14}\n", "up (m/s)", "Us (m/s)", "p (Pa)",
             "rho (kg/m3)", "E (J/kg)");
  for (const auto& r : rows) {
    fmt::print(out, "{:>12.6g} {:>12.6g} {:>14.6e} {:>14.6g} {:>14.6e}\n", r.up, r.us, r.p, r.rho,
               r.energy);
  }
}

void write_eos_csv(std::ostream& out, std::span<const EosSample> samples) {
  out << "rho_kg_per_m3,energy_J_per_kg,p_Pa,c_bulk_m_per_s,c_p_m_per_s,region\n";
  for (const auto& s : samples) {
    fmt::print(out, "{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{}\n", s.rho, s.energy, s.pressure,
               s.bulk_speed, s.soundspeed, s.region);
  }
}

void write_eos_table(std::ostream& out, std::span<const EosSample> samples) {
  fmt::print(out, "{:>14} {:>14} {:>14} {:>12} {:>12}  {}\n", "rho (kg/m3)", "E (J/kg)", "p (Pa)",
             "c_K (m/s)", "c_p (m/s)", "region");
  for (const auto& s : samples) {
    fmt::print(out, "{:>14.6g} {:>14.6e} {:>14.6e} {:>12.6g} {:>12.6g}  {}\n", s.rho, s.energy,
               s.pressure, s.bulk_speed, s.soundspeed, s.region);
  }
}

}  // namespace shatter
