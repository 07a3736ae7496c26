#include "scene/reader.hpp"

#include <cmath>

#include <fmt/format.h>

#include "shatter/io/suggest.hpp"

namespace shatter::scene {
namespace {

std::string_view type_name(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::table:
      return "a table";
    case toml::node_type::array:
      return "an array";
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a number";
    case toml::node_type::boolean:
      return "a boolean";
    default:
      return "a date/time";
  }
}

std::optional<double> as_number(const toml::node& n) {
  if (const auto* f = n.as_floating_point()) return f->get();
  if (const auto* i = n.as_integer()) return static_cast<double>(i->get());
  return std::nullopt;
}

}  // namespace

std::string location(const toml::source_region& where) {
  if (!where.path || where.path->empty()) return {};
  const std::string& p = *where.path;
  if (p.rfind("--set", 0) == 0) return fmt::format("command line ({})", p);
  return fmt::format("{}:{}", p, static_cast<unsigned>(where.begin.line));
}

Reader::Reader(toml::table& table, std::string path, std::string_view fallback_where)
    : table_(&table), path_(std::move(path)), fallback_where_(fallback_where) {}

void Reader::allow(std::initializer_list<std::string_view> keys) {
  for (auto k : keys) allowed_.emplace_back(k);
}

void Reader::allow(const std::vector<std::string>& keys) {
  allowed_.insert(allowed_.end(), keys.begin(), keys.end());
}

void Reader::reject_unknown() const {
  for (const auto& [k, v] : *table_) {
    const std::string_view key = k.str();
    if (std::find(allowed_.begin(), allowed_.end(), key) != allowed_.end()) continue;
    const std::string hint = io::did_you_mean(key, allowed_);
    std::string where_key = location(k.source());
    if (where_key.empty()) where_key = where(key);
    throw SceneError(where_key, key_path(key),
                     hint.empty()
                         ? fmt::format("unknown key (allowed here: {})", fmt::join(allowed_, ", "))
                         : fmt::format("unknown key{}", hint));
  }
}

std::string Reader::key_path(std::string_view key) const {
  return path_.empty() ? std::string(key) : fmt::format("{}.{}", path_, key);
}

std::string Reader::where(std::string_view key) const {
  if (const toml::node* n = find(key)) {
    std::string w = location(n->source());
    if (!w.empty()) return w;
  }
  std::string w = location(table_->source());
  if (!w.empty()) return w;
  return fallback_where_.empty() ? std::string("scene") : fallback_where_;
}

void Reader::fail(std::string_view key, const std::string& message) const {
  throw SceneError(where(key), key_path(key), message);
}

void Reader::fail_table(const std::string& message) const {
  std::string w = location(table_->source());
  if (w.empty()) w = fallback_where_.empty() ? std::string("scene") : fallback_where_;
  throw SceneError(w, path_, message);
}

const toml::node* Reader::find(std::string_view key) const {
  return table_->get(key);
}

const toml::node& Reader::require(std::string_view key) const {
  const toml::node* n = find(key);
  if (n == nullptr) fail(key, "is required but missing");
  return *n;
}

double Reader::number(std::string_view key) {
  const toml::node& n = require(key);
  const auto v = as_number(n);
  if (!v) fail(key, fmt::format("must be a number (got {})", type_name(n)));
  if (!std::isfinite(*v)) fail(key, fmt::format("must be finite (got {})", *v));
  return *v;
}

double Reader::number(std::string_view key, double fallback) {
  if (!has(key)) {
    table_->insert(key, fallback);
    return fallback;
  }
  return number(key);
}

std::optional<double> Reader::optional_number(std::string_view key) {
  if (!has(key)) return std::nullopt;
  return number(key);
}

std::int64_t Reader::integer(std::string_view key, std::int64_t fallback) {
  if (!has(key)) {
    table_->insert(key, fallback);
    return fallback;
  }
  const toml::node& n = require(key);
  const auto* i = n.as_integer();
  if (i == nullptr) fail(key, fmt::format("must be an integer (got {})", type_name(n)));
  return i->get();
}

bool Reader::boolean(std::string_view key, bool fallback) {
  if (!has(key)) {
    table_->insert(key, fallback);
    return fallback;
  }
  const toml::node& n = require(key);
  const auto* b = n.as_boolean();
  if (b == nullptr) fail(key, fmt::format("must be true or false (got {})", type_name(n)));
  return b->get();
}

std::string Reader::string(std::string_view key) {
  const toml::node& n = require(key);
  const auto* s = n.as_string();
  if (s == nullptr) fail(key, fmt::format("must be a string (got {})", type_name(n)));
  if (s->get().empty()) fail(key, "must not be empty");
  return s->get();
}

std::string Reader::string(std::string_view key, std::string_view fallback) {
  if (!has(key)) {
    table_->insert(key, std::string(fallback));
    return std::string(fallback);
  }
  return string(key);
}

std::optional<std::string> Reader::optional_string(std::string_view key) {
  if (!has(key)) return std::nullopt;
  return string(key);
}

std::string Reader::choice(std::string_view key, std::string_view fallback,
                           const std::vector<std::string>& choices) {
  std::string v = string(key, fallback);
  if (std::find(choices.begin(), choices.end(), v) == choices.end()) {
    const std::string hint = io::did_you_mean(v, choices);
    fail(key, fmt::format("unknown value '{}'{} (one of: {})", v, hint, fmt::join(choices, ", ")));
  }
  return v;
}

Eigen::Vector3d Reader::vec3(std::string_view key) {
  const toml::node& n = require(key);
  const auto* a = n.as_array();
  if (a == nullptr || a->size() != 3) {
    fail(key, fmt::format("must be an array of 3 numbers [x, y, z] (got {})",
                          a == nullptr ? type_name(n) : fmt::format("{} elements", a->size())));
  }
  Eigen::Vector3d v;
  for (std::size_t i = 0; i < 3; ++i) {
    const auto x = as_number(*a->get(i));
    if (!x || !std::isfinite(*x)) fail(key, fmt::format("element {} is not a finite number", i));
    v[static_cast<Eigen::Index>(i)] = *x;
  }
  return v;
}

Eigen::Vector3d Reader::vec3(std::string_view key, const Eigen::Vector3d& fallback) {
  if (!has(key)) {
    table_->insert(key, toml::array{fallback.x(), fallback.y(), fallback.z()});
    return fallback;
  }
  return vec3(key);
}

std::optional<Eigen::Vector3d> Reader::optional_vec3(std::string_view key) {
  if (!has(key)) return std::nullopt;
  return vec3(key);
}

toml::table* Reader::subtable(std::string_view key) {
  toml::node* n = table_->get(key);
  if (n == nullptr) return nullptr;
  auto* t = n->as_table();
  if (t == nullptr) fail(key, fmt::format("must be a table (got {})", type_name(*n)));
  return t;
}

double Reader::positive(std::string_view key, double v) const {
  if (!(v > 0.0)) fail(key, fmt::format("must be > 0 (got {})", v));
  return v;
}

double Reader::non_negative(std::string_view key, double v) const {
  if (!(v >= 0.0)) fail(key, fmt::format("must be >= 0 (got {})", v));
  return v;
}

}  // namespace shatter::scene

namespace shatter::scene {

double Reader::within(std::string_view key, double v, double lo, double hi, std::string_view unit,
                      std::string_view reason) const {
  if (!(v >= lo && v <= hi)) {
    fail(key, fmt::format("= {} {} is outside the range [{:g}, {:g}] {} ({})", v, unit, lo, hi,
                          unit, reason));
  }
  return v;
}

}  // namespace shatter::scene
