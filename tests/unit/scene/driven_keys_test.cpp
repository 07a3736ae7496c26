// The driven-body key body.NAME.driven (issue 10, the tensile rod's grips): default, resolved
// scene, and the errors that name the key (projectile of [impact], every body driven).

#include <gtest/gtest.h>

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

TEST(DrivenKeys, DefaultIsFreeAndTheKeyIsRead) {
  const Scene s = parse(kTinyScene);
  for (const auto& b : s.bodies) EXPECT_FALSE(b.driven) << b.name;
  const Scene t = parse(with(kTargetLine, kTargetLine + "\ndriven = true"));
  for (const auto& b : t.bodies) EXPECT_EQ(b.driven, b.name == "target") << b.name;
  EXPECT_NE(t.resolved.find("driven = true"), std::string::npos) << t.resolved;
}

TEST(DrivenKeys, AStringValueIsATypeErrorAtItsLine) {
  const std::string text = with(kTargetLine, kTargetLine + "\ndriven = \"yes\"");
  expect_names(error_of(text), line_of(text, "driven = "), "body.target.driven");
}

TEST(DrivenKeys, TheImpactProjectileCannotBeDriven) {
  const std::string text = with("material = \"nylon\"", "material = \"nylon\"\ndriven = true");
  const std::string msg = error_of(text);
  expect_names(msg, line_of(text, "driven = "), "body.projectile.driven");
  EXPECT_NE(msg.find("[impact]"), std::string::npos) << msg;
}

TEST(DrivenKeys, EveryBodyDrivenIsRefusedWhenTheSolverIsMade) {
  const std::string text = with("material = \"nylon\"", "material = \"nylon\"",
                                with(kTargetLine, kTargetLine + "\ndriven = true"));
  Scene s = parse(text);
  for (auto& b : s.bodies) b.driven = true;  // (the projectile cannot say so in the file)
  try {
    (void)make_solver(s, ParticleStore{}, {}, 1);
    FAIL() << "no error with every body driven";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("driven"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("nothing is left free"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace shatter::scene
