#include "scene/document.hpp"

#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "scene/reader.hpp"

namespace shatter::scene {
namespace {

// A chain longer than this is surely a cycle.
constexpr int kMaxExtends = 8;

toml::table parse_text(std::string_view text, const std::string& source) {
  try {
    return toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    throw SceneError(location(e.source()), "",
                     fmt::format("TOML syntax error: {}", e.description()));
  }
}

std::string read_file(const std::filesystem::path& file, const std::string& where,
                      const std::string& key) {
  // Checked before opening: an ifstream opens a directory without complaint (the scene would
  // then be empty, "solver: is required but missing"), and a FIFO would block forever.
  std::error_code ec;
  const auto status = std::filesystem::status(file, ec);
  if (!std::filesystem::exists(status)) {
    throw SceneError(where, key, fmt::format("no such file: {}", file.string()));
  }
  if (std::filesystem::is_directory(status)) {
    throw SceneError(where, key, fmt::format("{} is a directory, not a scene file", file.string()));
  }
  if (!std::filesystem::is_regular_file(status)) {
    throw SceneError(where, key, fmt::format("{} is not a regular file", file.string()));
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) throw SceneError(where, key, fmt::format("cannot read {}", file.string()));
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Moves the overlay's values into `base` (tables merge key by key, anything else replaces), so
// each value keeps the source region of the file it came from.
void merge(toml::table& base, toml::table&& overlay) {
  for (auto&& [key, value] : overlay) {
    toml::node* existing = base.get(key.str());
    if (existing != nullptr && existing->is_table() && value.is_table()) {
      merge(*existing->as_table(), std::move(*value.as_table()));
    } else {
      base.insert_or_assign(key, std::move(value));
    }
  }
}

toml::table resolve_extends(toml::table doc, const std::filesystem::path& base_dir, int depth) {
  const toml::node* ext = doc.get("extends");
  if (ext == nullptr) return doc;
  const auto* name = ext->as_string();
  if (name == nullptr) throw SceneError(location(ext->source()), "extends", "must be a file name");
  if (depth >= kMaxExtends) {
    throw SceneError(location(ext->source()), "extends",
                     fmt::format("more than {} nested extends (a cycle?)", kMaxExtends));
  }
  const std::filesystem::path parent = base_dir / name->get();
  toml::table base = resolve_extends(
      parse_text(read_file(parent, location(ext->source()), "extends"), parent.string()),
      parent.parent_path(), depth + 1);
  doc.erase("extends");
  merge(base, std::move(doc));
  return base;
}

}  // namespace

toml::table load_document(const std::filesystem::path& file) {
  return parse_document(read_file(file, file.string(), ""), file.string(), file.parent_path());
}

toml::table parse_document(std::string_view text, const std::string& source,
                           const std::filesystem::path& base_dir) {
  return resolve_extends(parse_text(text, source), base_dir.empty() ? "." : base_dir, 0);
}

void apply_override(toml::table& doc, const std::string& assignment) {
  const std::string origin = "--set " + assignment;
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0) {
    throw SceneError(
        location(toml::source_region{{}, {}, std::make_shared<const std::string>(origin)}), "",
        "expected key=value");
  }
  const std::string key = assignment.substr(0, eq);
  const std::string value = assignment.substr(eq + 1);

  // The value as TOML if it is valid TOML, else as a bare string (--set body.a.material=granite).
  toml::table parsed;
  try {
    parsed = toml::parse("v = " + value, origin);
  } catch (const toml::parse_error&) {
    std::string quoted = "v = \"";
    for (char c : value) quoted += (c == '"' || c == '\\') ? std::string{'\\', c} : std::string{c};
    quoted += '"';
    parsed = toml::parse(quoted, origin);
  }

  toml::table* t = &doc;
  std::string walked;
  std::size_t start = 0;
  while (true) {
    const auto dot = key.find('.', start);
    const std::string part = key.substr(start, dot == std::string::npos ? dot : dot - start);
    if (part.empty()) throw SceneError(fmt::format("command line ({})", origin), key, "empty key");
    walked += (walked.empty() ? "" : ".") + part;
    if (dot == std::string::npos) {
      t->insert_or_assign(part, std::move(*parsed.get("v")));
      return;
    }
    toml::node* next = t->get(part);
    if (next == nullptr) {
      t->insert(part, toml::table{});
      next = t->get(part);
    }
    // A catalogue name stands for the table { name = ... }, so its parameters can be overridden
    // one by one: --set body.target.material.yield=30e6 on material = "basalt".
    if (part == "material" && next->is_string()) {
      const std::string name = next->as_string()->get();
      t->insert_or_assign(part, toml::table{{"name", name}});
      next = t->get(part);
    }
    if (!next->is_table()) {
      throw SceneError(fmt::format("command line ({})", origin), walked,
                       "is a value, not a table, so it has no sub-keys");
    }
    t = next->as_table();
    start = dot + 1;
  }
}

std::string to_toml(const toml::table& doc) {
  std::stringstream ss;
  ss << toml::toml_formatter(
      doc, toml::toml_formatter::default_flags & ~toml::format_flags::allow_literal_strings);
  return ss.str();
}

}  // namespace shatter::scene
