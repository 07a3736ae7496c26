// The [gravity] table (src/scene/parse_gravity.cpp): defaults, values read, and bad values
// refused with the key and its line.

#include <gtest/gtest.h>

#include "unit/scene/scene_fixture.hpp"

namespace shatter::scene {
namespace {

using test::error_of;
using test::expect_names;
using test::line_of;
using test::parse;
using test::with;

// The tiny scene without its symmetry plane (self-gravity needs the whole body), plus a table.
std::string with_gravity(const std::string& table) {
  return with("symmetry_plane = \"z\"\n", "",
              with("lo = [-0.05, -0.05, 0.0]", "lo = [-0.05, -0.05, -0.05]")) +
         "\n[gravity]\n" + table;
}

TEST(GravityKeys, AbsentTableMeansNoSelfGravity) {
  const Scene s = parse(test::kTinyScene);
  EXPECT_FALSE(s.solver.self_gravity.self);
  EXPECT_FALSE(s.solver.self_gravity.equilibrium);
}

TEST(GravityKeys, ValuesAreRead) {
  const Scene s = parse(with_gravity("self = true\nmesh = 48\nG = 1.0\nequilibrium = true\n"));
  EXPECT_TRUE(s.solver.self_gravity.self);
  EXPECT_EQ(s.solver.self_gravity.mesh, 48);
  EXPECT_EQ(s.solver.self_gravity.G, 1.0);
  EXPECT_TRUE(s.solver.self_gravity.equilibrium);
  EXPECT_NE(s.resolved.find("mesh = 48"), std::string::npos) << s.resolved;
}

TEST(GravityKeys, BadValuesAreRefusedAtTheirLine) {
  struct Case {
    std::string table, key, line;
  };
  for (const Case& c : {Case{"self = true\nmesh = 4\n", "gravity.mesh", "mesh = 4"},
                        Case{"self = true\nmeshh = 64\n", "gravity.meshh", "meshh = 64"},
                        Case{"self = true\nG = -1.0\n", "gravity.G", "G = -1.0"},
                        Case{"self = true\ndt_factor = 2.0\n", "gravity.dt_factor", "dt_factor"},
                        Case{"equilibrium = true\n", "gravity.equilibrium", "equilibrium"},
                        Case{"self = \"yes\"\n", "gravity.self", "self = "}}) {
    const std::string text = with_gravity(c.table);
    expect_names(error_of(text), line_of(text, c.line), c.key);
  }
}

TEST(GravityKeys, SymmetryPlaneIsRefused) {
  const std::string text = test::kTinyScene + "\n[gravity]\nself = true\n";
  const std::string msg = error_of(text);
  expect_names(msg, line_of(text, "self = true"), "gravity.self");
  EXPECT_NE(msg.find("symmetry"), std::string::npos) << msg;
}

}  // namespace
}  // namespace shatter::scene
