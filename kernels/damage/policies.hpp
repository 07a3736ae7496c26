#pragma once
// The damage models by name (DamageSpec::model in shatter/material/catalogue.hpp), for the
// materials engineer's make_material: make_damage_policy returns the policy as a variant, and
// std::visit on it instantiates the constitutive kernel once per policy type, so the inner loop
// has no model branch. Unknown model names and unknown parameter keys are errors, never silent
// fallbacks.
//
//   auto policy = shatter::damage::make_damage_policy(spec.model, spec.params);
//   return std::visit([&](auto p) -> MaterialPtr { return build<decltype(p)>(..., p); }, policy);
//
// Keys (SI units):
//   grady_kipp: crack_speed_factor (0.4), rs (0 = from particle volume), intact_soundspeed
//               (0 = current c_p), and the flaw keys read by shatter::flaw_spec_from_params:
//               weibull_m, weibull_k [m^-3], total_flaws, explicit_flaws (0 | 1), seed
//   brittle:    sigma_0 [Pa]            (required)
//   fatigue:    eps_0 [-]               (required)

#include <algorithm>
#include <array>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>

#include "damage/brittle.hpp"
#include "damage/damage_policy.hpp"
#include "damage/fatigue.hpp"
#include "damage/grady_kipp.hpp"

namespace shatter::damage {

using AnyDamage = std::variant<NoDamage, GradyKipp, Brittle, Fatigue>;

inline constexpr std::array<std::string_view, 4> kDamageModels{"none", "grady_kipp", "brittle",
                                                               "fatigue"};

namespace detail {

using Params = std::map<std::string, double>;

inline void check_keys(std::string_view model, const Params& params,
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

inline double get(std::string_view model, const Params& params, const std::string& key,
                  double fallback, bool required) {
  const auto it = params.find(key);
  if (it == params.end()) {
    if (required)
      throw std::invalid_argument("damage model '" + std::string(model) + "': missing parameter '" +
                                  key + "'");
    return fallback;
  }
  return it->second;
}

inline void require_positive(std::string_view model, const std::string& key, double v,
                             bool allow_zero) {
  if (!(v > 0.0 || (allow_zero && v == 0.0)))
    throw std::invalid_argument("damage model '" + std::string(model) + "': parameter '" + key +
                                "' must be " + (allow_zero ? "non-negative" : "positive"));
}

}  // namespace detail

inline AnyDamage make_damage_policy(std::string_view model, const detail::Params& params) {
  if (model == "none") {
    detail::check_keys(model, params, {});
    return NoDamage{};
  }
  if (model == "grady_kipp") {
    detail::check_keys(model, params,
                       {"crack_speed_factor", "rs", "intact_soundspeed", "min_intact_fraction",
                        "weibull_m", "weibull_k", "total_flaws", "explicit_flaws", "seed"});
    GradyKipp p;
    auto& g = p.params;
    g.crack_speed_factor =
        detail::get(model, params, "crack_speed_factor", g.crack_speed_factor, false);
    g.rs = detail::get(model, params, "rs", g.rs, false);
    g.intact_soundspeed =
        detail::get(model, params, "intact_soundspeed", g.intact_soundspeed, false);
    g.min_intact_fraction =
        detail::get(model, params, "min_intact_fraction", g.min_intact_fraction, false);
    detail::require_positive(model, "crack_speed_factor", g.crack_speed_factor, false);
    detail::require_positive(model, "rs", g.rs, true);
    detail::require_positive(model, "intact_soundspeed", g.intact_soundspeed, true);
    detail::require_positive(model, "min_intact_fraction", g.min_intact_fraction, false);
    return p;
  }
  if (model == "brittle") {
    detail::check_keys(model, params, {"sigma_0"});
    Brittle p;
    p.params.sigma_0 = detail::get(model, params, "sigma_0", 0.0, true);
    detail::require_positive(model, "sigma_0", p.params.sigma_0, false);
    return p;
  }
  if (model == "fatigue") {
    detail::check_keys(model, params, {"eps_0"});
    Fatigue p;
    p.params.eps_0 = detail::get(model, params, "eps_0", 0.0, true);
    detail::require_positive(model, "eps_0", p.params.eps_0, false);
    return p;
  }
  std::string list;
  for (auto m : kDamageModels) list += std::string(list.empty() ? "" : ", ") + std::string(m);
  throw std::invalid_argument("unknown damage model '" + std::string(model) + "' (known: " + list +
                              ")");
}

// Columns the chosen model keeps (to register before particles are created).
inline FieldSet damage_fields(const AnyDamage& policy) {
  return std::visit([](const auto& p) { return std::decay_t<decltype(p)>::kFields; }, policy);
}

}  // namespace shatter::damage
