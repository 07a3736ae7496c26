#pragma once
// The material catalogue (ISSUE materials, "Material catalogue"): named parameter sets, each with
// its source, loaded from TOML (data/materials.toml ships with shatter), validated on load, and
// turned into constitutive models. Implemented in src/materials/.

#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "shatter/material/material_model.hpp"

namespace shatter {

// One named parameter set. Model names and parameter keys are those of data/materials.toml;
// all values SI (Pa, kg/m^3, J/kg, m^-3).
struct MaterialSpec {
  std::string name;
  std::string source;    // literature reference for the numbers
  std::string eos;       // tillotson | tillotson_simplified | mie_gruneisen | linear_polynomial |
                         // linear_elastic | ideal_gas
  std::string strength;  // hydro | elastic | von_mises | linear_hardening | benz_asphaug |
                         // drucker_prager | lundborg | modified_lundborg
  // Compaction model of a porous material (issue 29; kernels/porosity): empty (none) |
  // eps_alpha | p_alpha. In a catalogue file the sub-table porosity = { model = "...", ... };
  // its parameters (alpha0, eps_e, kappa, ...) live in params with the others.
  std::string porosity{};
  std::map<std::string, double> params;

  double get(std::string_view key) const;  // throws naming the material and key if absent
};

// Damage model chosen for a material group (parameters per MPM paper Sec. 3.3 / BA95 Sec. 3).
struct DamageSpec {
  std::string model = "none";  // none | grady_kipp | brittle | fatigue
  std::map<std::string, double> params;
  // How D reaches the stress: total | incremental | lagged; empty = the default (lagged).
  // kernels/constitutive/composed_kernel.hpp (DamageCoupling) and docs/fracture.md.
  std::string coupling{};
};

class MaterialCatalogue {
 public:
  // Parses and validates a catalogue file; errors name the file, line and key.
  static MaterialCatalogue load(const std::filesystem::path& file);
  // The catalogue shipped in data/materials.toml.
  static MaterialCatalogue builtin();

  const MaterialSpec& get(std::string_view name) const;  // throws listing the known names
  bool contains(std::string_view name) const;
  std::vector<std::string> names() const;
  void add(MaterialSpec spec);  // validates first

 private:
  std::map<std::string, MaterialSpec, std::less<>> specs_;
};

// A parameter set that fails validation. key() is the offending parameter (or "eos",
// "strength", "model" for a bad model name), so that the catalogue loader can point at its line.
class MaterialError : public std::invalid_argument {
 public:
  MaterialError(const std::string& what, std::string key)
      : std::invalid_argument(what), key_(std::move(key)) {}
  const std::string& key() const { return key_; }

 private:
  std::string key_;
};

// Throws MaterialError (a std::invalid_argument) naming the material and the offending key when a
// parameter is non-physical (non-positive modulus, Poisson outside [0, 0.5), rho_iv >= rho0, Eiv >=
// Ecv, ...), or when a model name or parameter key is unknown.
void validate(const MaterialSpec& spec);

// Builds the constitutive model of one material group.
MaterialPtr make_material(const MaterialSpec& spec, const DamageSpec& damage = {});

}  // namespace shatter
