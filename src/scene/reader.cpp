#include "scene/reader.hpp"

#include <algorithm>
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

thread_local SchemaLog* g_log = nullptr;

// body.target.damage -> body.NAME.damage; solver.contact_pair[2] -> solver.contact_pair[].
std::string generic_path(const std::string& path) {
  std::string out;
  std::size_t start = 0;
  int part = 0;
  bool in_body = false;
  while (start <= path.size()) {
    const auto dot = path.find('.', start);
    std::string p = path.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    if (const auto br = p.find('['); br != std::string::npos) p = p.substr(0, br) + "[]";
    if (part == 0) in_body = p == "body";
    if (part == 1 && in_body) p = "NAME";
    out += (part == 0 ? "" : ".") + p;
    ++part;
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  return out;
}

template <class T>
void add_unique(std::vector<T>& v, const T& x) {
  if (std::find(v.begin(), v.end(), x) == v.end()) v.push_back(x);
}

std::string show(double v) {
  return fmt::format("{:g}", v);
}

}  // namespace

TableInfo& SchemaLog::table(const std::string& path) {
  if (!tables.count(path)) order.push_back(path);
  return tables[path];
}

SchemaLog* record_schema(SchemaLog* log) {
  SchemaLog* previous = g_log;
  g_log = log;
  return previous;
}

void Reader::note(std::string_view key, std::string_view type, std::optional<std::string> fallback,
                  bool required) const {
  if (g_log == nullptr) return;
  TableInfo& t = g_log->table(generic_path(path_));
  const std::string k(key);
  if (!t.keys.count(k)) t.order.push_back(k);
  KeyInfo& info = t.keys[k];
  if (!type.empty()) add_unique(info.types, std::string(type));
  if (fallback) add_unique(info.defaults, *fallback);
  if (required) info.required = true;
  if (!required && !fallback && !type.empty()) info.optional = true;
}

void Reader::note_type(std::string_view key, std::string_view type) const {
  if (g_log == nullptr) return;
  note(key, "", std::nullopt, false);
  g_log->table(generic_path(path_)).keys[std::string(key)].stated_type = std::string(type);
}

void Reader::note_default(std::string_view key, std::string_view text) const {
  if (g_log == nullptr) return;
  note(key, "", std::nullopt, false);
  g_log->table(generic_path(path_)).keys[std::string(key)].stated_default = std::string(text);
}

void Reader::note_range(std::string_view key, std::string_view range, std::string_view unit) const {
  if (g_log == nullptr) return;
  note(key, "", std::nullopt, false);
  KeyInfo& info = g_log->table(generic_path(path_)).keys[std::string(key)];
  if (!range.empty()) add_unique(info.ranges, std::string(range));
  if (!unit.empty() && info.unit.empty()) info.unit = std::string(unit);
}

std::string location(const toml::source_region& where) {
  if (!where.path || where.path->empty()) return {};
  const std::string& p = *where.path;
  if (p.rfind("--set", 0) == 0) return fmt::format("command line ({})", p);
  return fmt::format("{}:{}", p, static_cast<unsigned>(where.begin.line));
}

Reader::Reader(toml::table& table, std::string path, std::string_view fallback_where)
    : table_(&table), path_(std::move(path)), fallback_where_(fallback_where) {}

void Reader::allow(std::initializer_list<std::string_view> keys) {
  allow(std::vector<std::string>(keys.begin(), keys.end()));
}

void Reader::allow(const std::vector<std::string>& keys) {
  allowed_.insert(allowed_.end(), keys.begin(), keys.end());
  if (g_log != nullptr) {
    TableInfo& t = g_log->table(generic_path(path_));
    for (const auto& k : keys) add_unique(t.allowed, k);
  }
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
  note(key, "number", std::nullopt, true);
  return read_number(key);
}

double Reader::read_number(std::string_view key) {
  const toml::node& n = require(key);
  const auto v = as_number(n);
  if (!v) fail(key, fmt::format("must be a number (got {})", type_name(n)));
  if (!std::isfinite(*v)) fail(key, fmt::format("must be finite (got {})", *v));
  return *v;
}

double Reader::number(std::string_view key, double fallback) {
  note(key, "number", show(fallback), false);
  if (!has(key)) {
    table_->insert(key, fallback);
    return fallback;
  }
  return read_number(key);
}

std::optional<double> Reader::optional_number(std::string_view key) {
  note(key, "number", std::nullopt, false);
  if (!has(key)) return std::nullopt;
  return read_number(key);
}

std::int64_t Reader::integer(std::string_view key, std::int64_t fallback) {
  note(key, "integer", fmt::format("{}", fallback), false);
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
  note(key, "boolean", fallback ? "true" : "false", false);
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
  note(key, "string", std::nullopt, true);
  return read_string(key);
}

std::string Reader::read_string(std::string_view key) {
  const toml::node& n = require(key);
  const auto* s = n.as_string();
  if (s == nullptr) fail(key, fmt::format("must be a string (got {})", type_name(n)));
  if (s->get().empty()) fail(key, "must not be empty");
  return s->get();
}

std::string Reader::string(std::string_view key, std::string_view fallback) {
  note(key, "string", fmt::format("\"{}\"", fallback), false);
  if (!has(key)) {
    table_->insert(key, std::string(fallback));
    return std::string(fallback);
  }
  return read_string(key);
}

std::optional<std::string> Reader::optional_string(std::string_view key) {
  note(key, "string", std::nullopt, false);
  if (!has(key)) return std::nullopt;
  return read_string(key);
}

std::string Reader::choice(std::string_view key, std::string_view fallback,
                           const std::vector<std::string>& choices) {
  if (g_log != nullptr) {
    // An empty fallback means the key is required (shape).
    note(key, "choice",
         fallback.empty() ? std::nullopt : std::optional(fmt::format("\"{}\"", fallback)),
         fallback.empty());
    auto& info = g_log->table(generic_path(path_)).keys[std::string(key)];
    for (const auto& c : choices) add_unique(info.choices, c);
  }
  std::string v;
  if (!has(key)) {
    table_->insert(key, std::string(fallback));
    v = std::string(fallback);
  } else {
    v = read_string(key);
  }
  if (std::find(choices.begin(), choices.end(), v) == choices.end()) {
    const std::string hint = io::did_you_mean(v, choices);
    fail(key, fmt::format("unknown value '{}'{} (one of: {})", v, hint, fmt::join(choices, ", ")));
  }
  return v;
}

Eigen::Vector3d Reader::vec3(std::string_view key) {
  note(key, "[x, y, z]", std::nullopt, true);
  return read_vec3(key);
}

Eigen::Vector3d Reader::read_vec3(std::string_view key) {
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
  note(key, "[x, y, z]",
       fmt::format("[{}, {}, {}]", show(fallback.x()), show(fallback.y()), show(fallback.z())),
       false);
  if (!has(key)) {
    table_->insert(key, toml::array{fallback.x(), fallback.y(), fallback.z()});
    return fallback;
  }
  return read_vec3(key);
}

std::optional<Eigen::Vector3d> Reader::optional_vec3(std::string_view key) {
  note(key, "[x, y, z]", std::nullopt, false);
  if (!has(key)) return std::nullopt;
  return read_vec3(key);
}

toml::table* Reader::subtable(std::string_view key) {
  note(key, "table", std::nullopt, false);
  toml::node* n = table_->get(key);
  if (n == nullptr) return nullptr;
  auto* t = n->as_table();
  if (t == nullptr) fail(key, fmt::format("must be a table (got {})", type_name(*n)));
  return t;
}

double Reader::positive(std::string_view key, double v) const {
  note_range(key, "> 0");
  if (!(v > 0.0)) fail(key, fmt::format("must be > 0 (got {})", v));
  return v;
}

double Reader::non_negative(std::string_view key, double v) const {
  note_range(key, ">= 0");
  if (!(v >= 0.0)) fail(key, fmt::format("must be >= 0 (got {})", v));
  return v;
}

}  // namespace shatter::scene

namespace shatter::scene {

double Reader::within(std::string_view key, double v, double lo, double hi, std::string_view unit,
                      std::string_view reason) const {
  if (g_log != nullptr) {
    // "m (|coordinate|)": the unit, then what of the value is bounded.
    const auto space = unit.find(' ');
    const std::string what =
        space == std::string_view::npos ? "" : std::string(unit.substr(space + 1)) + " ";
    note_range(key, fmt::format("{}in [{:g}, {:g}]", what, lo, hi));
    auto& info = g_log->table(generic_path(path_)).keys[std::string(key)];
    if (info.unit.empty()) info.unit = std::string(unit.substr(0, space));
  }
  if (!(v >= lo && v <= hi)) {
    fail(key, fmt::format("= {} {} is outside the range [{:g}, {:g}] {} ({})", v, unit, lo, hi,
                          unit, reason));
  }
  return v;
}

}  // namespace shatter::scene
