// The contact keys of [solver] (issue 11 item 3): solver.contact, solver.friction and
// [[solver.contact_pair]]; defaults, the pair's body names resolved to body ids, and errors that
// name the key.

#include <gtest/gtest.h>

#include "scene_fixture.hpp"

namespace shatter::scene {
namespace {

using test::error_of;
using test::expect_names;
using test::kTinyScene;
using test::line_of;
using test::parse;
using test::with;

const std::string kSolverLine = "symmetry_plane = \"z\"";

TEST(ContactKeys, DefaultIsTheSharedFieldWithoutFriction) {
  const Scene s = parse(kTinyScene);
  EXPECT_EQ(s.solver.contact.kind, ContactKind::single_field);
  EXPECT_EQ(s.solver.contact.friction, 0.0);
  EXPECT_TRUE(s.solver.contact.pairs.empty());
  EXPECT_NE(s.resolved.find("contact = \"single_field\""), std::string::npos) << s.resolved;
}

TEST(ContactKeys, MultiFieldWithAPairResolvesBodyNamesToIds) {
  const std::string text =
      with(kSolverLine, kSolverLine +
                            "\ncontact = \"multi_field\"\nfriction = 0.2\n"
                            "contact_pair = [{ bodies = [\"projectile\", \"target\"], "
                            "friction = 0.5 }]");
  const Scene s = parse(text);
  EXPECT_EQ(s.solver.contact.kind, ContactKind::multi_field);
  EXPECT_EQ(s.solver.contact.friction, 0.2);
  ASSERT_EQ(s.solver.contact.pairs.size(), 1u);
  // Body ids are the order of scene.bodies (build sets IField::body to it).
  std::int64_t target = -1, projectile = -1;
  for (std::size_t g = 0; g < s.bodies.size(); ++g) {
    (s.bodies[g].name == "target" ? target : projectile) = static_cast<std::int64_t>(g);
  }
  EXPECT_EQ(s.solver.contact.coefficient(target, projectile), 0.5);
  EXPECT_EQ(s.solver.contact.coefficient(projectile, target), 0.5);
  // --set works as for any key.
  const Scene t = parse(kTinyScene, {"solver.contact=\"multi_field\"", "solver.friction=0.5"});
  EXPECT_EQ(t.solver.contact.kind, ContactKind::multi_field);
  EXPECT_EQ(t.solver.contact.coefficient(0, 1), 0.5);
}

TEST(ContactKeys, UnknownContactValueNamesTheKeyAndTheChoices) {
  const std::string text = with(kSolverLine, kSolverLine + "\ncontact = \"multi\"");
  const std::string msg = error_of(text);
  expect_names(msg, line_of(text, "contact = "), "solver.contact");
  EXPECT_NE(msg.find("multi_field"), std::string::npos) << msg;
}

TEST(ContactKeys, FrictionNeedsMultiFieldAndIsNonNegative) {
  const std::string single = with(kSolverLine, kSolverLine + "\nfriction = 0.5");
  expect_names(error_of(single), line_of(single, "friction"), "solver.friction");
  const std::string negative =
      with(kSolverLine, kSolverLine + "\ncontact = \"multi_field\"\nfriction = -0.5");
  expect_names(error_of(negative), line_of(negative, "friction"), "solver.friction");
}

TEST(ContactKeys, PairNamingAnUnknownBodyOrOneBodyTwiceIsRefused) {
  const std::string unknown =
      with(kSolverLine, kSolverLine +
                            "\ncontact = \"multi_field\"\n"
                            "contact_pair = [{ bodies = [\"projectile\", \"boulder\"], "
                            "friction = 0.5 }]");
  const std::string msg = error_of(unknown);
  EXPECT_NE(msg.find("solver.contact_pair[0].bodies"), std::string::npos) << msg;
  EXPECT_NE(msg.find("no body named 'boulder'"), std::string::npos) << msg;
  const std::string twice =
      with(kSolverLine, kSolverLine +
                            "\ncontact = \"multi_field\"\n"
                            "contact_pair = [{ bodies = [\"target\", \"target\"], friction = 1 }]");
  EXPECT_NE(error_of(twice).find("two different bodies"), std::string::npos);
  const std::string extra =
      with(kSolverLine, kSolverLine +
                            "\ncontact = \"multi_field\"\n"
                            "contact_pair = [{ bodies = [\"target\", \"projectile\"], mu = 1 }]");
  EXPECT_NE(error_of(extra).find("solver.contact_pair[0].mu"), std::string::npos);
}

}  // namespace
}  // namespace shatter::scene
