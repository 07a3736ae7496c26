#pragma once
// Checked access to one TOML table of a scene: every read names its key, every failure throws a
// SceneError with the file and line of the offending value, unknown keys are errors with a "did
// you mean" hint, and defaults are written back into the table so that the resolved scene shows
// every value the run used.

#include <cstdint>
#include <initializer_list>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>
#include <Eigen/Core>

#include "shatter/scene/scene_error.hpp"

namespace shatter::scene {

// "file:line" for a value, or "command line (--set k=v)" for an override.
std::string location(const toml::source_region& where);

// What the readers of all scenes read while a SchemaLog is active: per table (body names and
// array indices generalised: body.NAME, parts[]), the keys allowed and, per key, its types,
// defaults, unit and ranges. The scene reference is generated from it (src/scene/reference.cpp),
// so the documentation lists exactly what the reader accepts.
struct KeyInfo {
  std::vector<std::string> types;
  std::vector<std::string> defaults;  // one per distinct value seen
  bool required = false;
  bool optional = false;  // may be left out, no default (optional_number, ...)
  std::string unit;
  std::vector<std::string> ranges;
  std::vector<std::string> choices;
  std::string stated_type;     // note_type: replaces the types the getters recorded
  std::string stated_default;  // note_default: replaces the defaults seen (derived ones)
};
struct TableInfo {
  std::vector<std::string> allowed;
  std::vector<std::string> order;  // keys in the order first seen
  std::map<std::string, KeyInfo> keys;
};
struct SchemaLog {
  std::vector<std::string> order;  // tables in the order first seen
  std::map<std::string, TableInfo> tables;
  TableInfo& table(const std::string& path);
};
// Sets the log the Readers of this thread record into (nullptr: none); returns the previous.
SchemaLog* record_schema(SchemaLog* log);

class Reader {
 public:
  Reader(toml::table& table, std::string path, std::string_view fallback_where = {});

  // Declares the keys this table may hold and rejects any other (with the closest allowed key).
  void allow(std::initializer_list<std::string_view> keys);
  void allow(const std::vector<std::string>& keys);
  void reject_unknown() const;

  bool has(std::string_view key) const { return table_->contains(key); }
  const std::string& path() const { return path_; }
  std::string key_path(std::string_view key) const;
  toml::table& table() { return *table_; }

  double number(std::string_view key);  // required
  double number(std::string_view key, double fallback);
  std::optional<double> optional_number(std::string_view key);
  std::int64_t integer(std::string_view key, std::int64_t fallback);
  bool boolean(std::string_view key, bool fallback);
  std::string string(std::string_view key);  // required
  std::string string(std::string_view key, std::string_view fallback);
  std::optional<std::string> optional_string(std::string_view key);
  // One of `choices`; an unknown value lists them and suggests the closest.
  std::string choice(std::string_view key, std::string_view fallback,
                     const std::vector<std::string>& choices);
  Eigen::Vector3d vec3(std::string_view key);  // required
  Eigen::Vector3d vec3(std::string_view key, const Eigen::Vector3d& fallback);
  std::optional<Eigen::Vector3d> optional_vec3(std::string_view key);
  // A sub-table; none when absent. An existing non-table value is an error.
  toml::table* subtable(std::string_view key);

  // Range checks on a value already read; they fail at the key's line.
  double positive(std::string_view key, double v) const;
  double non_negative(std::string_view key, double v) const;
  // v in [lo, hi] (src/scene/ranges.hpp), else an error stating the range, its unit and reason.
  double within(std::string_view key, double v, double lo, double hi, std::string_view unit,
                std::string_view reason) const;

  // For the scene reference (docs/scenes.md, src/scene/reference.cpp): the type of a key read
  // without the typed getters above, and a range checked by hand rather than with within().
  void note_type(std::string_view key, std::string_view type) const;
  // A default that depends on other values ("end_time / 10"), or "*required*".
  void note_default(std::string_view key, std::string_view text) const;
  // `range` may be empty when only the unit is worth recording.
  void note_range(std::string_view key, std::string_view range, std::string_view unit = {}) const;

  [[noreturn]] void fail(std::string_view key, const std::string& message) const;
  [[noreturn]] void fail_table(const std::string& message) const;
  std::string where(std::string_view key) const;

 private:
  double read_number(std::string_view key);
  std::string read_string(std::string_view key);
  Eigen::Vector3d read_vec3(std::string_view key);
  // Records the key in the active SchemaLog (none outside the reference generator).
  void note(std::string_view key, std::string_view type, std::optional<std::string> fallback,
            bool required) const;
  const toml::node* find(std::string_view key) const;
  const toml::node& require(std::string_view key) const;

  toml::table* table_;
  std::string path_;
  std::string fallback_where_;
  std::vector<std::string> allowed_;
};

}  // namespace shatter::scene
