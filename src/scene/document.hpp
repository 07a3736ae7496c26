#pragma once
// A scene's TOML document: the file, anything it extends, and the --set overrides, merged into
// one table whose values keep the file and line they came from.

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

namespace shatter::scene {

toml::table load_document(const std::filesystem::path& file);
toml::table parse_document(std::string_view text, const std::string& source,
                           const std::filesystem::path& base_dir);

// Applies "dotted.key=value" to the document (creating tables on the way).
void apply_override(toml::table& doc, const std::string& assignment);

// Serialises a document as TOML.
std::string to_toml(const toml::table& doc);

}  // namespace shatter::scene
