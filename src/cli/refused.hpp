#pragma once
// How `shatter run` and `check` report a scene refused while it is read and set up.

#include <filesystem>
#include <stdexcept>

#include <spdlog/spdlog.h>

#include "shatter/scene/scene.hpp"

namespace shatter::cli {

// Runs `read` (the scene's reading and set-up); true when it refused the scene, after reporting
// why: a SceneError names its key and line itself, any other refusal is prefixed with the file.
template <class Read>
bool refused(const std::filesystem::path& scene_file, Read&& read) {
  try {
    read();
  } catch (const scene::SceneError& err) {
    spdlog::error("{}", err.what());
    return true;
  } catch (const std::invalid_argument& err) {
    spdlog::error("{}: {}", scene_file.string(), err.what());
    return true;
  }
  return false;
}

}  // namespace shatter::cli
