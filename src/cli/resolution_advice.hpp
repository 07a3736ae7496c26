#pragma once
// `shatter check`'s resolution advice (resolution_advice.cpp).

#include <string>
#include <vector>

#include "shatter/scene/scene.hpp"

namespace shatter::cli {

// Lines to print: each body's radius in cells (CPPR, MPM) and in points, and warnings when the
// projectile has fewer than 10 cells per radius or a body is smaller than two cells.
std::vector<std::string> resolution_advice(const scene::Scene& s);

}  // namespace shatter::cli
