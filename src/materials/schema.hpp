#pragma once
// The parameter keys each model name accepts (data/materials.toml). One table for validation,
// the catalogue loader and the error messages that list what is allowed.

#include <string>
#include <string_view>
#include <vector>

namespace shatter::materials {

struct ModelSchema {
  std::string_view name;
  std::vector<std::string_view> required;
  std::vector<std::string_view> optional;
};

const std::vector<ModelSchema>& eos_schemas();
const std::vector<ModelSchema>& strength_schemas();
// Compaction models (MaterialSpec::porosity; kernels/porosity/porosity.hpp).
const std::vector<ModelSchema>& porosity_schemas();

// nullptr when the name is unknown.
const ModelSchema* find_eos(std::string_view name);
const ModelSchema* find_strength(std::string_view name);
const ModelSchema* find_porosity(std::string_view name);

// "a, b, c" for messages.
std::string join_names(const std::vector<ModelSchema>& models);
std::string join_names(const std::vector<std::string_view>& names);

}  // namespace shatter::materials
