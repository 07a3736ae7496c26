#include "materials/schema.hpp"

namespace shatter::materials {

const std::vector<ModelSchema>& eos_schemas() {
  static const std::vector<ModelSchema> k = {
      {"tillotson", {"A", "B", "a", "b", "E0", "Eiv", "Ecv", "rho_iv", "alpha", "beta"}, {}},
      {"tillotson_simplified", {"A", "a", "b"}, {}},
      {"mie_gruneisen", {"c0", "s", "gamma0"}, {}},
      {"linear_polynomial", {"C1"}, {"C0", "C2", "C3", "C4", "C5", "C6"}},
      // bulk_modulus, or else K from the strength model's elastic constants.
      {"linear_elastic", {}, {"bulk_modulus"}},
      {"ideal_gas", {"gamma"}, {}},
  };
  return k;
}

const std::vector<ModelSchema>& strength_schemas() {
  // Elastic constants are given as (young, poisson) or as (shear_modulus, bulk_modulus); the
  // validator checks that exactly one pair is complete, so both pairs are "optional" here.
  static const std::vector<ModelSchema> k = {
      {"hydro", {}, {}},
      {"elastic", {}, {}},
      {"von_mises", {"yield"}, {}},
      {"linear_hardening", {"yield", "plastic_modulus"}, {}},
      {"benz_asphaug", {"yield"}, {}},
      {"drucker_prager", {"cohesion", "friction", "dilatancy", "tension_cutoff"}, {}},
      // tension_cutoff: the optional tension cut-off p_t <= 0 (kernels/strength/lundborg.hpp).
      {"lundborg",
       {"cohesion", "friction_intact", "friction_damaged", "strength_limit"},
       {"melt_energy", "tension_cutoff"}},
      {"modified_lundborg",
       {"cohesion", "friction_intact", "friction_damaged", "strength_limit", "dilatancy"},
       {"melt_heat", "tension_cutoff"}},
  };
  return k;
}

const std::vector<ModelSchema>& porosity_schemas() {
  // eps_alpha: Wuennemann et al. 2006 with Collins et al. 2011's chi; p_alpha: Jutzi et al. 2008
  // (kernels/porosity/crush.hpp).
  static const std::vector<ModelSchema> k = {
      // deviator_scaling, compaction_damage: the porous bulk's strength and damage
      // (kernels/porosity/porosity.hpp), switches 0 / 1.
      {"eps_alpha",
       {"alpha0", "eps_e", "kappa", "eps_x"},
       {"chi", "deviator_scaling", "compaction_damage"}},
      {"p_alpha",
       {"alpha0", "p_e", "p_s"},
       {"crush_exponent", "c_e", "deviator_scaling", "compaction_damage", "p_t", "alpha_t",
        "crush_exponent_2"}},
  };
  return k;
}

namespace {
const ModelSchema* find_in(const std::vector<ModelSchema>& v, std::string_view name) {
  for (const auto& m : v) {
    if (m.name == name) return &m;
  }
  return nullptr;
}
}  // namespace

const ModelSchema* find_eos(std::string_view name) {
  return find_in(eos_schemas(), name);
}
const ModelSchema* find_strength(std::string_view name) {
  return find_in(strength_schemas(), name);
}
const ModelSchema* find_porosity(std::string_view name) {
  return find_in(porosity_schemas(), name);
}

std::string join_names(const std::vector<ModelSchema>& models) {
  std::string s;
  for (const auto& m : models) {
    if (!s.empty()) s += ", ";
    s += m.name;
  }
  return s;
}

std::string join_names(const std::vector<std::string_view>& names) {
  std::string s;
  for (const auto& n : names) {
    if (!s.empty()) s += ", ";
    s += n;
  }
  return s;
}

}  // namespace shatter::materials
