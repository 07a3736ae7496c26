#include "materials/damage_factory.hpp"

#include <algorithm>
#include <array>
#include <initializer_list>
#include <stdexcept>

#include <fmt/format.h>

namespace shatter::materials {
namespace {

using damage::Brittle;
using damage::Fatigue;
using damage::GradyKipp;
using damage::NoDamage;
using Params = std::map<std::string, double>;

constexpr std::array<std::string_view, 4> kDamageModels{"none", "grady_kipp", "brittle", "fatigue"};

void check_keys(std::string_view model, const Params& params,
                std::initializer_list<std::string_view> allowed) {
  for (const auto& [key, value] : params) {
    if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
      std::string list;
      for (auto a : allowed) list += std::string(list.empty() ? "" : ", ") + std::string(a);
      throw std::invalid_argument("damage model '" + std::string(model) + "': unknown parameter '" +
                                  key + "' (known: " + (list.empty() ? "none" : list) + ")");
    }
  }
}

double get(std::string_view model, const Params& params, const std::string& key, double fallback,
           bool required) {
  const auto it = params.find(key);
  if (it == params.end()) {
    if (required)
      throw std::invalid_argument("damage model '" + std::string(model) + "': missing parameter '" +
                                  key + "'");
    return fallback;
  }
  return it->second;
}

void require_positive(std::string_view model, const std::string& key, double v, bool allow_zero) {
  if (!(v > 0.0 || (allow_zero && v == 0.0)))
    throw std::invalid_argument("damage model '" + std::string(model) + "': parameter '" + key +
                                "' must be " + (allow_zero ? "non-negative" : "positive"));
}

// The one parameter of a one-parameter model (brittle: sigma_0, fatigue: eps_0): required and
// positive, and no other key allowed.
double sole_parameter(std::string_view model, const Params& params, const char* key) {
  check_keys(model, params, {key});
  const double v = get(model, params, key, 0.0, true);
  require_positive(model, key, v, false);
  return v;
}

GradyKipp make_grady_kipp(std::string_view model, const Params& params) {
  check_keys(model, params,
             {"crack_speed_factor", "rs", "intact_soundspeed", "min_intact_fraction", "weibull_m",
              "weibull_k", "total_flaws", "explicit_flaws", "seed"});
  GradyKipp p;
  auto& g = p.params;
  g.crack_speed_factor = get(model, params, "crack_speed_factor", g.crack_speed_factor, false);
  g.rs = get(model, params, "rs", g.rs, false);
  g.intact_soundspeed = get(model, params, "intact_soundspeed", g.intact_soundspeed, false);
  g.min_intact_fraction = get(model, params, "min_intact_fraction", g.min_intact_fraction, false);
  require_positive(model, "crack_speed_factor", g.crack_speed_factor, false);
  require_positive(model, "rs", g.rs, true);
  require_positive(model, "intact_soundspeed", g.intact_soundspeed, true);
  require_positive(model, "min_intact_fraction", g.min_intact_fraction, false);
  return p;
}

}  // namespace

AnyDamage make_damage_policy(std::string_view model, const Params& params) {
  if (model == "none") {
    check_keys(model, params, {});
    return NoDamage{};
  }
  if (model == "grady_kipp") return make_grady_kipp(model, params);
  if (model == "brittle") {
    Brittle p;
    p.params.sigma_0 = sole_parameter(model, params, "sigma_0");
    return p;
  }
  if (model == "fatigue") {
    Fatigue p;
    p.params.eps_0 = sole_parameter(model, params, "eps_0");
    return p;
  }
  std::string list;
  for (auto m : kDamageModels) list += std::string(list.empty() ? "" : ", ") + std::string(m);
  throw std::invalid_argument("unknown damage model '" + std::string(model) + "' (known: " + list +
                              ")");
}

AnyDamage make_damage(const DamageSpec& spec, double young) {
  AnyDamage d = make_damage_policy(spec.model, spec.params);
  if (spec.model != "none" && !(young > 0.0)) {
    throw std::invalid_argument(fmt::format(
        "damage model '{}' needs the material's Young's modulus (Eq. 18): give young and poisson, "
        "or shear_modulus and bulk_modulus",
        spec.model));
  }
  return d;
}

constitutive::DamageCoupling damage_coupling(const DamageSpec& spec) {
  using constitutive::DamageCoupling;
  if (spec.coupling.empty()) return constitutive::kDefaultCoupling;
  for (auto c : {DamageCoupling::total, DamageCoupling::incremental, DamageCoupling::lagged}) {
    if (spec.coupling == constitutive::coupling_name(c)) return c;
  }
  throw std::invalid_argument(
      fmt::format("damage: unknown value '{}' of 'coupling' (known: total, incremental, lagged)",
                  spec.coupling));
}

}  // namespace shatter::materials
