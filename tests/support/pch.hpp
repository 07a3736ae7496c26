// The test programs' precompiled header (tests/CMakeLists.txt): GoogleTest, Eigen's core and the
// standard headers most tests include. Parsing them was about half of a typical test file's
// compile time (gtest.h 1.7 s, Eigen/Core 2.2 s of a 7.6 s file, measured in session 17), and
// the test programs are compiled twice in CI (Release, then ASan+UBSan). Only third-party and
// standard headers belong here: they do not change while the project is edited, so a change to
// a shatter header still rebuilds only the tests that include it. A file where GCC 12 then
// reports a false positive inside the standard headers (tests/CMakeLists.txt names one) skips the
// precompiled header.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>
