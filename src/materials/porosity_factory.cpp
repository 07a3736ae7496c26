#include "materials/porosity_factory.hpp"

#include <string>
#include <string_view>

#include <fmt/format.h>

namespace shatter::materials {

namespace {

double opt(const MaterialSpec& s, const char* key, double fallback) {
  const auto it = s.params.find(key);
  return it == s.params.end() ? fallback : it->second;
}

[[noreturn]] void fail(const MaterialSpec& spec, std::string_view key, const std::string& why) {
  throw MaterialError(fmt::format("material '{}': '{}' = {} {} (porosity '{}')", spec.name, key,
                                  spec.get(key), why, spec.porosity),
                      std::string(key));
}

void require(const MaterialSpec& spec, std::string_view key, bool ok, const char* why) {
  if (!ok) fail(spec, key, why);
}

// The sources' defaults of the strength and damage switches (kernels/porosity/porosity.hpp):
// JBM08 scales the deviator and damages the matrix on compaction with P-alpha; W06 and CMW11
// (eps-alpha) do neither.
double degradation_default(const MaterialSpec& s) {
  return s.porosity == "p_alpha" ? 1.0 : 0.0;
}

// JBM09's two-stage crush curve (kernels/porosity/crush.hpp): p_t and alpha_t together, the
// transition inside the plastic range and alpha_t between the full compaction and alpha0.
void check_two_stage(const MaterialSpec& spec, double a0, double pe, double ps) {
  const bool has_pt = spec.params.count("p_t") != 0, has_at = spec.params.count("alpha_t") != 0;
  if (!has_pt && !has_at) {
    if (spec.params.count("crush_exponent_2") != 0) {
      require(spec, "crush_exponent_2", false, "needs the two-stage curve's p_t and alpha_t");
    }
    return;
  }
  if (!has_pt) require(spec, "alpha_t", false, "needs p_t (the two-stage curve's transition)");
  if (!has_at) require(spec, "p_t", false, "needs alpha_t (1 + the slow stage's amplitude)");
  const double pt = spec.get("p_t"), at = spec.get("alpha_t");
  require(spec, "p_t", pt > pe && pt <= ps, "must be in (p_e, p_s]");
  require(spec, "alpha_t", at >= 1.0 && at <= a0, "must be in [1, alpha0]");
  if (!(opt(spec, "crush_exponent_2", 2.0) > 0.0)) {
    require(spec, "crush_exponent_2", false, "must be > 0");
  }
}

}  // namespace

void check_porosity(const MaterialSpec& spec) {
  if (spec.porosity.empty()) return;
  for (const char* k : {"deviator_scaling", "compaction_damage"}) {
    const double v = opt(spec, k, degradation_default(spec));
    if (v != 0.0 && v != 1.0) require(spec, k, false, "must be 0 (off) or 1 (on)");
  }
  const double a0 = spec.get("alpha0");
  require(spec, "alpha0", a0 >= 1.0 && a0 <= 100.0,
          "must be in [1, 100] (distension rho_s / rho: 1 is solid, 100 is 99% porosity)");
  if (spec.porosity == "eps_alpha") {
    const double ee = spec.get("eps_e"), k = spec.get("kappa"), ex = spec.get("eps_x");
    require(spec, "eps_e", ee <= 0.0 && ee > -1.0,
            "must be in (-1, 0] (the volumetric strain where compaction starts; < 0 is "
            "compression)");
    // kappa > 1 would compact the pores faster than the bulk shrinks: the matrix would expand
    // under compression (d ln rho_s = -(1 - kappa) d eps_V, W06 Sec. 2).
    require(spec, "kappa", k > 0.0 && k <= 1.0, "must be in (0, 1]");
    require(spec, "eps_x", ex <= ee, "must be <= eps_e (the exponential regime starts at eps_e)");
    const double chi = opt(spec, "chi", 1.0);
    if (!(chi > 0.0 && chi <= 1.0)) {
      require(spec, "chi", false, "must be in (0, 1] (c_e / c_s: the porous body is not stiffer)");
    }
  } else if (spec.porosity == "p_alpha") {
    const double pe = spec.get("p_e"), ps = spec.get("p_s");
    require(spec, "p_e", pe >= 0.0, "must be >= 0 Pa");
    require(spec, "p_s", ps > pe, "must exceed p_e (full compaction above the elastic limit)");
    if (!(opt(spec, "crush_exponent", 2.0) > 0.0)) {
      require(spec, "crush_exponent", false, "must be > 0");
    }
    if (!(opt(spec, "c_e", 0.0) >= 0.0)) require(spec, "c_e", false, "must be >= 0 m/s");
    check_two_stage(spec, a0, pe, ps);
  }
}

porosity::Porous make_porosity(const MaterialSpec& s) {
  porosity::Porous m = make_crush(s);
  const double d = degradation_default(s);
  m.set_degradation(opt(s, "deviator_scaling", d) == 1.0, opt(s, "compaction_damage", d) == 1.0);
  return m;
}

porosity::Porous make_crush(const MaterialSpec& s) {
  if (s.porosity == "eps_alpha") {
    porosity::EpsAlphaParams q;
    q.alpha0 = s.get("alpha0");
    q.eps_e = s.get("eps_e");
    q.kappa = s.get("kappa");
    q.eps_x = s.get("eps_x");
    q.chi = opt(s, "chi", 1.0);
    return porosity::Porous::eps_alpha(q, s.get("rho0"));
  }
  porosity::PAlphaParams q;
  q.alpha0 = s.get("alpha0");
  q.p_e = s.get("p_e");
  q.p_s = s.get("p_s");
  q.n = opt(s, "crush_exponent", 2.0);
  q.c_e = opt(s, "c_e", 0.0);
  q.p_t = opt(s, "p_t", 0.0);
  q.alpha_t = opt(s, "alpha_t", 1.0);
  q.n2 = opt(s, "crush_exponent_2", 2.0);
  return porosity::Porous::p_alpha(q);
}

}  // namespace shatter::materials
