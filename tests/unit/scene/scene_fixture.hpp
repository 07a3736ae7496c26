#pragma once
// A small valid scene (a lab impact in miniature) and helpers to break it one line at a time.

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "shatter/scene/scene.hpp"

namespace shatter::test {

inline const std::string kTinyScene = R"(name = "tiny"
description = "a small lab impact"

[solver]
cell_size = 2.0e-3
end_time = 1.0e-6
symmetry_plane = "z"

[domain]
lo = [-0.05, -0.05, 0.0]
hi = [0.05, 0.05, 0.05]
boundary = "outflow"

[body.target]
shape = "sphere"
centre = [0.0, 0.0, 0.0]
radius = 0.01
material = "basalt"

[body.target.damage]
model = "grady_kipp"
weibull_m = 8.5
weibull_k = 3.0e39
total_flaws = 1.0e9

[body.projectile]
shape = "sphere"
radius = 3.5e-3
material = "nylon"

[impact]
projectile = "projectile"
target = "target"
speed = 3200.0
angle = 30.0

[output]
snapshot_every = 0.5e-6
)";

// kTinyScene with the first occurrence of `from` replaced by `to`.
inline std::string with(const std::string& from, const std::string& to,
                        std::string text = kTinyScene) {
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << "fixture lacks: " << from;
  if (pos != std::string::npos) text.replace(pos, from.size(), to);
  return text;
}

// 1-based line of the first occurrence of `what` in `text`.
inline int line_of(const std::string& text, const std::string& what) {
  const auto pos = text.find(what);
  EXPECT_NE(pos, std::string::npos) << what;
  return 1 +
         static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(pos), '\n'));
}

inline scene::Scene parse(const std::string& text, const std::vector<std::string>& sets = {}) {
  return scene::parse_scene(text, "tiny.toml", sets);
}

// Parses `text` expecting a SceneError; returns its message.
inline std::string error_of(const std::string& text, const std::vector<std::string>& sets = {}) {
  try {
    parse(text, sets);
  } catch (const scene::SceneError& e) {
    return e.what();
  }
  ADD_FAILURE() << "scene was accepted but should not be";
  return {};
}

// The message names the file and line, and the dotted key.
inline void expect_names(const std::string& msg, int line, const std::string& key) {
  EXPECT_NE(msg.find("tiny.toml:" + std::to_string(line) + ":"), std::string::npos)
      << "expected line " << line << " in: " << msg;
  EXPECT_NE(msg.find(key), std::string::npos) << "expected key " << key << " in: " << msg;
}

}  // namespace shatter::test
