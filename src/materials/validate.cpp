// Validation of a parameter set (catalogue.hpp): every key known to its models, every value
// finite and physical. Each error names the material and the offending key.

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include <fmt/format.h>

#include "materials/elastic_constants.hpp"
#include "materials/porosity_factory.hpp"
#include "materials/schema.hpp"
#include "shatter/material/catalogue.hpp"

namespace shatter {

namespace {

using materials::ModelSchema;

// Keys every material may carry besides those of its models: the reference density, the two
// ways of giving the elastic constants and whether those follow the EOS (shear_from_eos).
constexpr std::string_view kCommonKeys[] = {"rho0",          "young",        "poisson",
                                            "shear_modulus", "bulk_modulus", "shear_from_eos"};

[[noreturn]] void fail(const MaterialSpec& spec, std::string_view key, const std::string& why) {
  throw MaterialError(fmt::format("material '{}': '{}' {}", spec.name, key, why), std::string(key));
}

class Checker {
 public:
  explicit Checker(const MaterialSpec& spec) : spec_(spec) {}

  double value(std::string_view key) const { return spec_.params.find(std::string(key))->second; }
  bool has(std::string_view key) const { return spec_.params.count(std::string(key)) != 0; }

  void positive(std::string_view key) const {
    if (has(key) && !(value(key) > 0.0))
      fail(spec_, key, fmt::format("= {} must be > 0", value(key)));
  }
  void non_negative(std::string_view key) const {
    if (has(key) && !(value(key) >= 0.0))
      fail(spec_, key, fmt::format("= {} must be >= 0", value(key)));
  }
  void non_positive(std::string_view key) const {
    if (has(key) && !(value(key) <= 0.0))
      fail(spec_, key, fmt::format("= {} must be <= 0 (tension is negative pressure)", value(key)));
  }

 private:
  const MaterialSpec& spec_;
};

void check_keys(const MaterialSpec& spec, const ModelSchema& eos, const ModelSchema& strength,
                const ModelSchema& por) {
  std::set<std::string_view> allowed(std::begin(kCommonKeys), std::end(kCommonKeys));
  for (const auto* m : {&eos, &strength, &por}) {
    allowed.insert(m->required.begin(), m->required.end());
    allowed.insert(m->optional.begin(), m->optional.end());
  }
  for (const auto& [key, v] : spec.params) {
    if (!allowed.count(key)) {
      fail(spec, key,
           fmt::format("is not a parameter of eos '{}', strength '{}' or porosity '{}' (allowed: "
                       "{})",
                       eos.name, strength.name, por.name.empty() ? "none" : por.name,
                       materials::join_names(
                           std::vector<std::string_view>(allowed.begin(), allowed.end()))));
    }
    if (!std::isfinite(v)) fail(spec, key, "is not a finite number");
  }
  if (!spec.params.count("rho0")) fail(spec, "rho0", "is missing (reference density, kg/m^3)");
  for (const auto* m : {&eos, &strength, &por}) {
    for (auto key : m->required) {
      if (!spec.params.count(std::string(key))) {
        fail(spec, key, fmt::format("is missing (required by '{}')", m->name));
      }
    }
  }
}

void check_eos(const MaterialSpec& spec, const Checker& c) {
  c.positive("rho0");
  const std::string& e = spec.eos;
  if (e == "tillotson") {
    for (auto k : {"A", "E0", "Eiv", "Ecv"}) c.positive(k);
    for (auto k : {"B", "a", "b", "alpha", "beta", "rho_iv"}) c.non_negative(k);
    if (!(c.value("Eiv") < c.value("Ecv")))
      fail(spec, "Eiv", fmt::format("= {} must be < Ecv = {}", c.value("Eiv"), c.value("Ecv")));
    if (!(c.value("rho_iv") < c.value("rho0")))
      fail(spec, "rho_iv",
           fmt::format("= {} must be < rho0 = {}", c.value("rho_iv"), c.value("rho0")));
  } else if (e == "tillotson_simplified") {
    c.positive("A");
    c.non_negative("a");
    c.non_negative("b");
  } else if (e == "mie_gruneisen") {
    c.positive("c0");
    c.non_negative("s");
    c.non_negative("gamma0");
  } else if (e == "linear_polynomial") {
    c.positive("C1");
  } else if (e == "linear_elastic") {
    c.positive("bulk_modulus");
    if (!c.has("bulk_modulus") && !materials::has_elastic_pair(spec))
      fail(spec, "bulk_modulus",
           "is missing (linear_elastic needs bulk_modulus, or young and poisson)");
  } else if (e == "ideal_gas") {
    if (!(c.value("gamma") > 1.0))
      fail(spec, "gamma", fmt::format("= {} must be > 1", c.value("gamma")));
  }
}

void check_strength(const MaterialSpec& spec, const Checker& c) {
  const std::string& s = spec.strength;
  // Elastic constants: needed by every model with shear; optional for hydro (damage uses them).
  if (s != "hydro" || materials::has_any_elastic_key(spec)) materials::elastic_constants(spec);
  // shear_from_eos: 0 (constant G, the default) or 1 (G from the EOS's bulk modulus at the
  // Poisson ratio of the elastic constants; docs/materials.md, "Shear modulus from the EOS").
  if (c.has("shear_from_eos")) {
    const double v = c.value("shear_from_eos");
    if (v != 0.0 && v != 1.0) {
      fail(spec, "shear_from_eos",
           fmt::format("= {} must be 0 (constant shear modulus) or 1 (G from the EOS's bulk "
                       "modulus at the Poisson ratio)",
                       v));
    }
    if (v == 1.0 && s == "hydro") {
      fail(spec, "shear_from_eos", "= 1 needs a strength model with shear (strength is 'hydro')");
    }
  }
  if (s == "von_mises" || s == "benz_asphaug" || s == "linear_hardening") {
    c.positive("yield");
    c.non_negative("plastic_modulus");
  } else if (s == "drucker_prager") {
    c.non_negative("cohesion");
    c.non_negative("friction");
    c.non_negative("dilatancy");
    c.non_positive("tension_cutoff");
    // The shear strength q_phi p + Y0 must not be negative on the admissible side of the cut-off.
    const double pt = c.value("tension_cutoff");
    if (c.value("friction") * pt + c.value("cohesion") < 0.0)
      fail(spec, "tension_cutoff",
           fmt::format("= {} lies beyond the cone apex -cohesion/friction = {}", pt,
                       -c.value("cohesion") / c.value("friction")));
  } else if (s == "lundborg" || s == "modified_lundborg") {
    c.positive("cohesion");
    c.positive("friction_intact");
    c.non_negative("friction_damaged");
    c.non_negative("dilatancy");
    c.non_negative("melt_energy");
    c.non_negative("melt_heat");
    // The tension cut-off (optional): a pressure p_t <= 0 below which p is clipped; p_t > 0
    // would put compressed material on the cut-off.
    c.non_positive("tension_cutoff");
    if (!(c.value("strength_limit") > c.value("cohesion")))
      fail(spec, "strength_limit",
           fmt::format("= {} must exceed cohesion = {}", c.value("strength_limit"),
                       c.value("cohesion")));
  }
}

// Physically meaningful ranges (docs/reliability.md): a value outside is a unit mistake or a
// typo, and at the extremes the models overflow. Generous on purpose: gases and vapour to the
// densest metals, very weak regolith (no lower bound on strength but the sign checks above) to
// diamond. Keys of models not listed here are checked by sign only.
struct Range {
  std::string_view keys;  // space separated, checked in this order
  double lo, hi;
  std::string_view unit, reason;
};
constexpr std::string_view kModulusReason =
    "up to 8x diamond's Young's modulus, 1.2e12 Pa, the stiffest known solid";
constexpr Range kRanges[] = {
    {"rho0", 1e-6, 1e5, "kg/m^3",
     "from a thin gas to 4x osmium, the densest element (22 590 kg/m^3)"},
    {"young shear_modulus bulk_modulus A B C1", 0.0, 1e13, "Pa", kModulusReason},
    {"poisson", -1.0, 0.5, "", "thermodynamic stability of an isotropic solid"},
    {"yield cohesion strength_limit", 0.0, 1e12, "Pa",
     "up to 10x the ideal strength of diamond, ~1e11 Pa"},
    {"plastic_modulus", 0.0, 1e13, "Pa", kModulusReason},
    {"E0 Eiv Ecv", 0.0, 1e10, "J/kg",
     "up to 20x the largest published Tillotson energy, basalt's E0 = 4.87e8 J/kg"},
    {"c0", 0.0, 1e5, "m/s", "5x the fastest sound speed in a solid (diamond, 18 km/s)"},
};

void check_ranges(const MaterialSpec& spec, const Checker& c) {
  for (const Range& r : kRanges) {
    for (std::string_view keys = r.keys; !keys.empty();) {
      const std::size_t end = std::min(keys.find(' '), keys.size());
      const std::string_view key = keys.substr(0, end);
      keys.remove_prefix(std::min(end + 1, keys.size()));
      if (!c.has(key)) continue;
      const double v = c.value(key);
      if (!(v >= r.lo && v <= r.hi)) {
        fail(spec, key,
             fmt::format("= {} {} is outside the range [{:g}, {:g}] {} ({})", v, r.unit, r.lo, r.hi,
                         r.unit, r.reason));
      }
    }
  }
}

}  // namespace

void validate(const MaterialSpec& spec) {
  if (spec.name.empty()) throw MaterialError("material with an empty name", "name");
  const ModelSchema* eos = materials::find_eos(spec.eos);
  if (eos == nullptr) {
    fail(spec, "eos",
         fmt::format("= '{}' is not a known equation of state (known: {})", spec.eos,
                     materials::join_names(materials::eos_schemas())));
  }
  const ModelSchema* strength = materials::find_strength(spec.strength);
  if (strength == nullptr) {
    fail(spec, "strength",
         fmt::format("= '{}' is not a known strength model (known: {})", spec.strength,
                     materials::join_names(materials::strength_schemas())));
  }
  static const ModelSchema kNoPorosity{"", {}, {}};
  const ModelSchema* por =
      spec.porosity.empty() ? &kNoPorosity : materials::find_porosity(spec.porosity);
  if (por == nullptr) {
    fail(spec, "porosity",
         fmt::format("= '{}' is not a known compaction model (known: {})", spec.porosity,
                     materials::join_names(materials::porosity_schemas())));
  }
  check_keys(spec, *eos, *strength, *por);
  const Checker c(spec);
  check_eos(spec, c);
  check_strength(spec, c);
  check_ranges(spec, c);
  materials::check_porosity(spec);
}

double MaterialSpec::get(std::string_view key) const {
  const auto it = params.find(std::string(key));
  if (it == params.end()) {
    throw MaterialError(fmt::format("material '{}': parameter '{}' is missing", name, key),
                        std::string(key));
  }
  return it->second;
}

}  // namespace shatter
