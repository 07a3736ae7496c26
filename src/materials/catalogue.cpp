// MaterialCatalogue: named parameter sets from TOML (data/materials.toml), validated on load.
//
// File format: one table per material,
//   [basalt]
//   source = "..."          # literature reference (required)
//   eos = "tillotson"       # model names, see schema.cpp
//   strength = "linear_hardening"
//   rho0 = 2700.0           # every other key is a numeric parameter, SI units
//   porosity = { model = "eps_alpha", alpha0 = 1.5, ... }   # optional compaction model
//                           # (issue 29), its parameters numeric as the others
// Errors name the file, the line and the key.

#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "shatter/material/catalogue.hpp"
#include "shatter/material/catalogue_path.hpp"

#ifndef SHATTER_SOURCE_DIR
#error "SHATTER_SOURCE_DIR must be defined (the build defines it for area libraries)"
#endif

namespace shatter {

namespace {

[[noreturn]] void fail_at(const std::filesystem::path& file, const toml::source_region& where,
                          const std::string& what) {
  throw std::invalid_argument(
      fmt::format("{}:{}: {}", file.string(), static_cast<unsigned>(where.begin.line), what));
}

std::string string_key(const std::filesystem::path& file, const std::string& material,
                       const toml::table& t, const char* key) {
  const toml::node* n = t.get(key);
  if (n == nullptr) {
    fail_at(file, t.source(), fmt::format("material '{}': '{}' is missing", material, key));
  }
  const auto v = n->value<std::string>();
  if (!v || v->empty()) {
    fail_at(file, n->source(),
            fmt::format("material '{}': '{}' must be a non-empty string", material, key));
  }
  return *v;
}

double number_key(const std::filesystem::path& file, const std::string& material,
                  const std::string& key, const toml::node& v) {
  if (!v.is_number()) {
    fail_at(file, v.source(),
            fmt::format("material '{}': '{}' must be a number (SI units)", material, key));
  }
  return *v.value<double>();
}

// porosity = { model = "...", key = number, ... }: the model into spec.porosity, the numbers into
// spec.params (schema.cpp lists the keys; validate() refuses others and names them).
void read_porosity(const std::filesystem::path& file, const toml::node& n, MaterialSpec& spec) {
  const toml::table* t = n.as_table();
  if (t == nullptr) {
    fail_at(file, n.source(),
            fmt::format("material '{}': 'porosity' must be a table {{ model = \"eps_alpha\" | "
                        "\"p_alpha\", ... }}",
                        spec.name));
  }
  spec.porosity = string_key(file, spec.name, *t, "model");
  for (auto&& [k, v] : *t) {
    const std::string key(k.str());
    if (key == "model") continue;
    spec.params[key] = number_key(file, spec.name, "porosity." + key, v);
  }
}

MaterialSpec read_material(const std::filesystem::path& file, const std::string& name,
                           const toml::table& t) {
  MaterialSpec spec;
  spec.name = name;
  spec.source = string_key(file, name, t, "source");
  spec.eos = string_key(file, name, t, "eos");
  spec.strength = string_key(file, name, t, "strength");
  for (auto&& [k, v] : t) {
    const std::string key(k.str());
    if (key == "source" || key == "eos" || key == "strength") continue;
    if (key == "porosity") {
      read_porosity(file, v, spec);
      continue;
    }
    spec.params[key] = number_key(file, name, key, v);
  }
  try {
    validate(spec);
  } catch (const MaterialError& e) {
    const toml::node* n = t.get(e.key());
    if (n == nullptr && t.get_as<toml::table>("porosity") != nullptr) {
      const toml::table& pt = *t.get_as<toml::table>("porosity");
      n = e.key() == "porosity" ? pt.get("model") : pt.get(e.key());
    }
    fail_at(file, n != nullptr ? n->source() : t.source(), e.what());
  }
  return spec;
}

}  // namespace

MaterialCatalogue MaterialCatalogue::load(const std::filesystem::path& file) {
  toml::table root;
  try {
    root = toml::parse_file(file.string());
  } catch (const toml::parse_error& e) {
    fail_at(file, e.source(), fmt::format("TOML syntax error: {}", e.description()));
  }
  MaterialCatalogue cat;
  for (auto&& [k, v] : root) {
    const std::string name(k.str());
    const toml::table* t = v.as_table();
    if (t == nullptr) {
      fail_at(file, v.source(),
              fmt::format("'{}' must be a table [{}] of material parameters", name, name));
    }
    cat.specs_[name] = read_material(file, name, *t);
  }
  if (cat.specs_.empty()) {
    throw std::invalid_argument(fmt::format("{}: no materials defined", file.string()));
  }
  return cat;
}

std::filesystem::path builtin_catalogue_path() {
  namespace fs = std::filesystem;
  std::error_code ec;
  // An explicit setting wins, and a wrong one is an error rather than silently passed over.
  if (const char* dir = std::getenv("SHATTER_DATA_DIR"); dir != nullptr && *dir != '\0') {
    const fs::path p = fs::path(dir) / "materials.toml";
    if (fs::is_regular_file(p, ec)) return p;
    throw std::invalid_argument(
        fmt::format("SHATTER_DATA_DIR={}: no materials.toml there ({})", dir, p.string()));
  }
  std::vector<fs::path> tried;
  // The installed layout (GNUInstallDirs): PREFIX/bin/shatter and PREFIX/share/shatter/.
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    tried.push_back(exe.parent_path().parent_path() / "share" / "shatter" / "materials.toml");
  }
  tried.push_back(fs::path(SHATTER_SOURCE_DIR) / "data" / "materials.toml");
  for (const fs::path& p : tried) {
    if (fs::is_regular_file(p, ec)) return p;
  }
  std::string list;
  for (const fs::path& p : tried) list += (list.empty() ? "" : ", ") + p.string();
  throw std::invalid_argument(fmt::format(
      "the material catalogue was not found (looked for {}); set SHATTER_DATA_DIR to the folder "
      "holding materials.toml",
      list));
}

MaterialCatalogue MaterialCatalogue::builtin() {
  return load(builtin_catalogue_path());
}

const MaterialSpec& MaterialCatalogue::get(std::string_view name) const {
  const auto it = specs_.find(name);
  if (it == specs_.end()) {
    std::string known;
    for (const auto& [n, s] : specs_) known += (known.empty() ? "" : ", ") + n;
    throw std::invalid_argument(fmt::format("unknown material '{}' (known: {})", name, known));
  }
  return it->second;
}

bool MaterialCatalogue::contains(std::string_view name) const {
  return specs_.find(name) != specs_.end();
}

std::vector<std::string> MaterialCatalogue::names() const {
  std::vector<std::string> out;
  for (const auto& [n, s] : specs_) out.push_back(n);
  return out;
}

void MaterialCatalogue::add(MaterialSpec spec) {
  validate(spec);
  std::string name = spec.name;
  specs_[std::move(name)] = std::move(spec);
}

}  // namespace shatter
