#pragma once
// A scene that cannot be run: the message names the file, the line and the key at fault, e.g.
//   scenes/lab-impact.toml:31: body.target.radius: must be > 0 (got -0.03)

#include <stdexcept>
#include <string>

namespace shatter::scene {

class SceneError : public std::runtime_error {
 public:
  // `where` is "file:line" (or "command line (--set ...)"), `key` the dotted key.
  SceneError(std::string where, std::string key, const std::string& message)
      : std::runtime_error(where + ": " + (key.empty() ? "" : key + ": ") + message),
        where_(std::move(where)),
        key_(std::move(key)) {}
  const std::string& where() const { return where_; }
  const std::string& key() const { return key_; }

 private:
  std::string where_;
  std::string key_;
};

}  // namespace shatter::scene
