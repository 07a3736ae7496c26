#include "materials/elastic_constants.hpp"

#include <fmt/format.h>

namespace shatter::materials {

namespace {
bool has(const MaterialSpec& s, const char* k) {
  return s.params.count(k) != 0;
}

[[noreturn]] void fail(const MaterialSpec& spec, const char* key, const std::string& why) {
  throw MaterialError(fmt::format("material '{}': '{}' {}", spec.name, key, why), key);
}
}  // namespace

bool has_elastic_pair(const MaterialSpec& s) {
  return (has(s, "young") && has(s, "poisson")) ||
         (has(s, "shear_modulus") && has(s, "bulk_modulus"));
}

bool has_any_elastic_key(const MaterialSpec& s) {
  return has(s, "young") || has(s, "poisson") || has(s, "shear_modulus");
}

namespace {
// The constants as given: (young, poisson) or (shear_modulus, bulk_modulus).
strength::ElasticConstants given_constants(const MaterialSpec& spec) {
  if (has(spec, "young") || has(spec, "poisson")) {
    if (!has(spec, "young")) fail(spec, "young", "is missing (given with poisson)");
    if (!has(spec, "poisson")) fail(spec, "poisson", "is missing (given with young)");
    const double e = spec.get("young");
    const double nu = spec.get("poisson");
    if (!(e > 0.0)) fail(spec, "young", fmt::format("= {} must be > 0", e));
    if (!(nu >= 0.0 && nu < 0.5))
      fail(spec, "poisson", fmt::format("= {} must be in [0, 0.5)", nu));
    return strength::ElasticConstants::from_young_poisson(e, nu);
  }
  if (!has(spec, "shear_modulus"))
    fail(spec, "young", "is missing (give young and poisson, or shear_modulus and bulk_modulus)");
  if (!has(spec, "bulk_modulus")) fail(spec, "bulk_modulus", "is missing (given shear_modulus)");
  const double g = spec.get("shear_modulus");
  const double k = spec.get("bulk_modulus");
  if (!(g > 0.0)) fail(spec, "shear_modulus", fmt::format("= {} must be > 0", g));
  if (!(k > 0.0)) fail(spec, "bulk_modulus", fmt::format("= {} must be > 0", k));
  // Isotropic relations: E = 9KG/(3K+G), nu = (3K-2G)/(2(3K+G)).
  const double nu = (3.0 * k - 2.0 * g) / (2.0 * (3.0 * k + g));
  if (!(nu >= 0.0))
    fail(spec, "shear_modulus",
         fmt::format("= {} gives a negative Poisson ratio {} with bulk_modulus {}", g, nu, k));
  return {9.0 * k * g / (3.0 * k + g), nu, g, k};
}

}  // namespace

strength::ElasticConstants elastic_constants(const MaterialSpec& spec) {
  strength::ElasticConstants el = given_constants(spec);
  // shear_from_eos = 1: G and K follow the EOS's bulk modulus at this Poisson ratio
  // (kernels/strength/strength_common.hpp, ElasticConstants::from_eos).
  el.from_eos = has(spec, "shear_from_eos") && spec.get("shear_from_eos") == 1.0;
  return el;
}

}  // namespace shatter::materials
