// Porous bodies in a scene (issue 29): body.NAME.porosity overrides the porous material's initial
// distension (alpha0 = 1 / (1 - porosity)) and is refused, naming the key and its line, when it is
// not physical or the material is not porous; the default snapshot columns carry the distension
// exactly when a body is porous.

#include <gtest/gtest.h>

#include <algorithm>

#include "scene_fixture.hpp"
#include "shatter/scene/build.hpp"

namespace shatter::scene {
namespace {

using test::error_of;
using test::expect_names;
using test::kTinyScene;
using test::line_of;
using test::parse;
using test::with;

const std::string kTargetLine = "material = \"basalt\"";
const std::string kPorousTarget = "material = \"porous_basalt\"";

std::string porous(const std::string& extra = "") {
  return with(kTargetLine, kPorousTarget + extra);
}

const BodySpec& target(const Scene& s) {
  return *std::find_if(s.bodies.begin(), s.bodies.end(),
                       [](const BodySpec& b) { return b.name == "target"; });
}

bool has_distension(const Scene& s) {
  const auto& c = s.output.columns;
  return std::find(c.begin(), c.end(), "distension") != c.end();
}

TEST(PorosityKeys, PorosityOverridesTheMaterialsAlpha0) {
  // The catalogue's porous_basalt has alpha0 = 1.25 (20% porosity).
  EXPECT_DOUBLE_EQ(target(parse(porous())).material.params.at("alpha0"), 1.25);
  const Scene s = parse(porous("\nporosity = 0.35"));
  // alpha0 = 1 / (1 - 0.35), the same double the reader computes
  EXPECT_DOUBLE_EQ(target(s).material.params.at("alpha0"), 1.0 / 0.65);
  // (written at full precision: 0.34999999999999998)
  EXPECT_NE(s.resolved.find("porosity = 0.3"), std::string::npos) << s.resolved;
  // zero porosity is the solid matrix: alpha0 = 1
  EXPECT_EQ(target(parse(porous("\nporosity = 0.0"))).material.params.at("alpha0"), 1.0);
}

TEST(PorosityKeys, TheBodyIsBuiltAtTheBulkDensityOfThatPorosity) {
  // rho = rho_s (1 - phi): the matrix density of basalt (2700 kg/m^3) times 0.65.
  const Scene s = parse(porous("\nporosity = 0.35"));
  const auto materials = build_materials(s);
  const auto& bodies = s.bodies;
  const auto g =
      static_cast<std::size_t>(std::find_if(bodies.begin(), bodies.end(),
                                            [](const BodySpec& b) { return b.name == "target"; }) -
                               bodies.begin());
  const double rho_s = target(s).material.params.at("rho0");
  // one division and one multiplication apart: a few ulps
  EXPECT_NEAR(materials[g]->reference_density(), rho_s * 0.65, 1e-12 * rho_s);
}

// body.mass is the body's mass: for a porous body it fixes the bulk density (mass / V), and the
// matrix density rho0 = alpha0 mass / V follows (before, it set rho0 = mass / V: the body then
// weighed mass / alpha0).
TEST(PorosityKeys, MassSetsTheBulkMassOfAPorousBody) {
  const double radius = 0.01, mass = 9.0e-3;
  const double volume = 4.0 / 3.0 * 3.14159265358979323846 * radius * radius * radius;
  for (const std::string extra : {"", "\nporosity = 0.35"}) {
    const Scene s = parse(porous(extra + "\nmass = 9.0e-3"));
    const auto& m = target(s).material;
    const double alpha0 = m.params.at("alpha0");
    EXPECT_GT(alpha0, 1.2) << extra;  // porous_basalt's 1.25, or 1 / 0.65
    const auto materials = build_materials(s);
    const auto g = static_cast<std::size_t>(&target(s) - s.bodies.data());
    // bulk density times the sphere's exact volume is the mass given: a few ulps apart
    EXPECT_NEAR(materials[g]->reference_density() * volume, mass, 1e-12 * mass) << extra;
    EXPECT_NEAR(m.params.at("rho0"), alpha0 * mass / volume, 1e-12 * m.params.at("rho0"));
  }
  // A dense body: rho0 is the bulk density, as before.
  const Scene d = parse(with(kTargetLine, kTargetLine + "\nmass = 9.0e-3"));
  EXPECT_NEAR(target(d).material.params.at("rho0") * volume, mass, 1e-12 * mass);
}

TEST(PorosityKeys, OutsideTheRangeIsRefusedAtItsLine) {
  for (const char* bad : {"porosity = 1.0", "porosity = -0.1", "porosity = 1.5"}) {
    const std::string text = porous(std::string("\n") + bad);
    const std::string msg = error_of(text);
    expect_names(msg, line_of(text, "porosity = "), "body.target.porosity");
    EXPECT_NE(msg.find("[0, 0.99]"), std::string::npos) << msg;
  }
}

TEST(PorosityKeys, ADenseMaterialIsRefusedAtItsLine) {
  const std::string text = with(kTargetLine, kTargetLine + "\nporosity = 0.3");
  const std::string msg = error_of(text);
  expect_names(msg, line_of(text, "porosity = "), "body.target.porosity");
  EXPECT_NE(msg.find("not porous"), std::string::npos) << msg;
}

TEST(PorosityKeys, PorosityWithAnAlpha0OverrideIsRefused) {
  const std::string text =
      with(kTargetLine, "material = { name = \"porous_basalt\", alpha0 = 1.5 }\nporosity = 0.3");
  const std::string msg = error_of(text);
  expect_names(msg, line_of(text, "porosity = "), "body.target.porosity");
  EXPECT_NE(msg.find("alpha0"), std::string::npos) << msg;
}

TEST(PorosityKeys, AStringIsATypeErrorAtItsLine) {
  const std::string text = porous("\nporosity = \"35%\"");
  expect_names(error_of(text), line_of(text, "porosity = "), "body.target.porosity");
}

TEST(PorosityKeys, DefaultColumnsCarryTheDistensionOnlyForAPorousScene) {
  EXPECT_FALSE(has_distension(parse(kTinyScene)));
  EXPECT_TRUE(has_distension(parse(porous())));
  // an explicit column list is the user's: not extended
  const std::string listed =
      with("snapshot_every = 0.5e-6", "snapshot_every = 0.5e-6\ncolumns = [\"x\", \"y\", \"z\"]",
           porous());
  EXPECT_FALSE(has_distension(parse(listed)));
}

}  // namespace
}  // namespace shatter::scene
