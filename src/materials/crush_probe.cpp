// The crush curve and the porous Hugoniot of a porous material (probe.hpp; issue 29), from the
// kernel's own porosity policy (kernels/porosity/porosity.hpp) and the matrix EOS.

// GCC 12 false positive inside AVX-512 intrinsics (PR 105593), see constitutive/simd.hpp; it
// must be silenced before the intrinsic headers are first included.
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ < 13
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif
#include <cmath>
#include <ostream>
#include <stdexcept>
#include <variant>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "materials/model_factory.hpp"
#include "materials/porosity_factory.hpp"
#include "shatter/material/probe.hpp"
#include "shatter/material/rest_compaction.hpp"

namespace shatter {

namespace {

void require_porous(const MaterialSpec& spec) {
  validate(spec);
  if (spec.porosity.empty()) {
    throw std::invalid_argument(
        fmt::format("material '{}' has no porosity (no crush curve)", spec.name));
  }
}

// Matrix density where the cold EOS gives pressure p (>= 0): bisection between rho0 and 3 rho0
// (every library EOS rises monotonically with rho at E = 0 in compression).
template <class Eos>
double cold_density(const Eos& eos, double rho0, double p) {
  double lo = rho0, hi = 3.0 * rho0;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    (eos.template evaluate<double>(mid, 0.0).p > p ? hi : lo) = mid;
  }
  return 0.5 * (lo + hi);
}

// The pressures of a P-alpha crush table: 0 to 1.2 p_s in equal steps; with JBM09's two-stage
// curve half the rows on [0, p_t] and half on (p_t, 1.2 p_s], so the steep stage (pumice: p_e =
// 1 MPa to p_t = 68 MPa, n = 12) is not hidden inside one step.
double p_alpha_row_pressure(const porosity::PAlphaParams& q, int k, int n) {
  if (q.p_t <= 0.0) return 1.2 * q.p_s * static_cast<double>(k) / (n - 1);
  const int half = n / 2;  // rows 0 .. half end at p_t
  if (k <= half) return q.p_t * static_cast<double>(k) / half;
  return q.p_t + (1.2 * q.p_s - q.p_t) * static_cast<double>(k - half) / (n - 1 - half);
}

}  // namespace

std::vector<CrushRow> crush_curve(const MaterialSpec& spec, int n) {
  require_porous(spec);
  if (n < 2) throw std::invalid_argument("crush curve: n must be >= 2");
  const porosity::Porous por = materials::make_porosity(spec);
  const double rho_s0 = spec.get("rho0"), rho00 = rho_s0 / por.alpha0();
  return std::visit(
      [&](const auto& eos) {
        std::vector<CrushRow> rows;
        for (int k = 0; k < n; ++k) {
          const double f = static_cast<double>(k) / (n - 1);
          CrushRow r;
          if (por.model() == porosity::Model::eps_alpha) {
            r.eps_v = 1.1 * por.eps_params().eps_c() * f + 0.0;  // + 0: no "-0" row
            r.alpha = por.crush_eps(r.eps_v);
            r.rho = rho00 * std::exp(-r.eps_v);
            r.pressure = por.bulk(eos, r.rho, 0.0, r.alpha).p;
          } else {
            r.pressure = p_alpha_row_pressure(por.p_params(), k, n);
            r.alpha = porosity::p_alpha_crush(por.p_params(), r.pressure);
            r.rho = cold_density(eos, rho_s0, r.alpha * r.pressure) / r.alpha;
            r.eps_v = std::log(rho00 / r.rho);
          }
          rows.push_back(r);
        }
        return rows;
      },
      materials::make_eos(spec));
}

std::vector<HugoniotRow> porous_hugoniot(const MaterialSpec& spec, std::span<const double> up) {
  require_porous(spec);
  const porosity::Porous por = materials::make_porosity(spec);
  const double rho_s0 = spec.get("rho0"), rho00 = rho_s0 / por.alpha0();
  return std::visit(
      [&](const auto& eos) {
        std::vector<HugoniotRow> rows;
        for (double u : up) {
          // E1 = up^2 / 2 from rest at p = 0; P_model(rho1) = rho00 up^2 rho1 / (rho1 - rho00).
          const double e1 = 0.5 * u * u;
          auto residual = [&](double rho1) {
            const double a = por.compact(eos, rho1, rho1, e1, por.alpha0());
            return por.bulk(eos, rho1, e1, a).p - rho00 * u * u * rho1 / (rho1 - rho00);
          };
          double lo = rho00 * (1.0 + 1e-9), hi = 2.0 * rho_s0;
          if (u <= 0.0 || !(residual(hi) > 0.0)) {
            throw std::runtime_error(fmt::format(
                "material '{}': no porous Hugoniot state at up = {} m/s", spec.name, u));
          }
          for (int i = 0; i < 200; ++i) {
            const double mid = 0.5 * (lo + hi);
            (residual(mid) > 0.0 ? hi : lo) = mid;
          }
          const double rho1 = 0.5 * (lo + hi), us = u * rho1 / (rho1 - rho00);
          rows.push_back({u, us, rho00 * us * u, rho1, e1});
        }
        return rows;
      },
      materials::make_eos(spec));
}

RestCompactionFn rest_compaction(const MaterialSpec& spec) {
  require_porous(spec);
  const porosity::Porous por = materials::make_porosity(spec);
  const double rho00 = spec.get("rho0") / por.alpha0();
  const bool stepped = por.model() == porosity::Model::eps_alpha && por.eps_params().chi != 1.0;
  return std::visit(
      [&](const auto& eos) -> RestCompactionFn {
        return [por, eos, rho00, stepped](double rho, double e) {
          double alpha = por.compact(eos, rho, rho00, e, por.alpha0());
          if (stepped && rho > rho00) {  // the monotone compression in kRestSteps steps
            alpha = por.alpha0();
            const double step = std::log(rho / rho00) / kRestSteps;
            double r_old = rho00;
            for (int k = 1; k <= kRestSteps; ++k) {
              const double r = k == kRestSteps ? rho : rho00 * std::exp(step * k);
              alpha = por.compact(eos, r, r_old, e, alpha);
              r_old = r;
            }
          }
          return RestCompaction{alpha, por.bulk(eos, rho, e, alpha).p};
        };
      },
      materials::make_eos(spec));
}

void write_crush_table(std::ostream& out, std::span<const CrushRow> rows) {
  fmt::print(out, "{:>12} {:>14} {:>10} {:>14}\n", "eps_V", "p (Pa)", "alpha", "rho (kg/m3)");
  for (const auto& r : rows) {
    fmt::print(out, "{:>12.5g} {:>14.6e} {:>10.6f} {:>14.6g}\n", r.eps_v, r.pressure, r.alpha,
               r.rho);
  }
}

void write_crush_csv(std::ostream& out, std::span<const CrushRow> rows) {
  out << "eps_v,p_Pa,alpha,rho_kg_per_m3\n";
  for (const auto& r : rows) {
    fmt::print(out, "{:.17g},{:.17g},{:.17g},{:.17g}\n", r.eps_v, r.pressure, r.alpha, r.rho);
  }
}

}  // namespace shatter
