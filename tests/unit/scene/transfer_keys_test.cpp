// The transfer keys of [solver] (issue 16): solver.transfer = "xpic" with solver.xpic_order, and
// solver.pic_fraction for the FLIP/PIC blend; defaults, and errors that name the key. The scene
// is the one place these rules are checked (mpm::TransferPolicy::from trusts it, issue 28).

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

std::string solver_with(const std::string& lines) {
  return with(kSolverLine, kSolverLine + "\n" + lines);
}

TEST(TransferKeys, DefaultIsPlainFlipAndResolvesWithoutTheNewKeys) {
  const Scene s = parse(kTinyScene);
  EXPECT_EQ(s.solver.transfer, TransferKind::flip);
  EXPECT_EQ(s.solver.pic_fraction, 0.0);
  // Scenes that do not use the blend resolve as before (no new keys written back).
  EXPECT_EQ(s.resolved.find("pic_fraction"), std::string::npos) << s.resolved;
  EXPECT_EQ(s.resolved.find("xpic_order"), std::string::npos) << s.resolved;
  EXPECT_EQ(s.resolved.find("fmpm_order"), std::string::npos) << s.resolved;
  EXPECT_EQ(s.resolved.find("filter_every"), std::string::npos) << s.resolved;
  EXPECT_EQ(s.solver.filter_every, 1);
  EXPECT_FALSE(s.solver.filter_heat);
  EXPECT_EQ(s.resolved.find("filter_heat"), std::string::npos) << s.resolved;
}

// solver.filter_heat: read with every filtering transfer, refused where nothing is filtered
// (plain FLIP, APIC; the message names the key and its line).
TEST(TransferKeys, FilterHeatOnlyWithAFilteringTransfer) {
  for (const std::string& lines : {std::string("transfer = \"xpic\"\nfilter_heat = true"),
                                   std::string("transfer = \"fmpm\"\nfilter_heat = true"),
                                   std::string("pic_fraction = 0.05\nfilter_heat = true")}) {
    EXPECT_TRUE(parse(solver_with(lines)).solver.filter_heat) << lines;
  }
  EXPECT_FALSE(parse(solver_with("filter_heat = false")).solver.filter_heat);
  for (const std::string& lines : {std::string("filter_heat = true"),
                                   std::string("transfer = \"apic\"\nfilter_heat = true")}) {
    const std::string text = solver_with(lines);
    expect_names(error_of(text), line_of(text, "filter_heat"), "solver.filter_heat");
  }
}

TEST(TransferKeys, FmpmTakesItsOrderAndThePeriodicFilter) {
  const Scene s = parse(solver_with("transfer = \"fmpm\"\nfmpm_order = 7\nfilter_every = 20"));
  EXPECT_EQ(s.solver.transfer, TransferKind::fmpm);
  EXPECT_EQ(s.solver.fmpm_order, 7);
  EXPECT_EQ(s.solver.filter_every, 20);
  const Scene d = parse(solver_with("transfer = \"fmpm\""));
  EXPECT_EQ(d.solver.fmpm_order, 5);
  EXPECT_EQ(d.solver.filter_every, 1);
  EXPECT_NE(d.resolved.find("fmpm_order = 5"), std::string::npos) << d.resolved;
  const Scene x = parse(solver_with("transfer = \"xpic\"\nxpic_order = 2\nfilter_every = 5"));
  EXPECT_EQ(x.solver.filter_every, 5);
}

TEST(TransferKeys, XpicTakesItsOrderAndDefaultsToFive) {
  const Scene s = parse(solver_with("transfer = \"xpic\"\nxpic_order = 3"));
  EXPECT_EQ(s.solver.transfer, TransferKind::xpic);
  EXPECT_EQ(s.solver.xpic_order, 3);
  const Scene d = parse(solver_with("transfer = \"xpic\""));
  EXPECT_EQ(d.solver.xpic_order, 5);
  EXPECT_NE(d.resolved.find("xpic_order = 5"), std::string::npos) << d.resolved;
  const Scene f = parse(solver_with("pic_fraction = 0.05"));
  EXPECT_EQ(f.solver.transfer, TransferKind::flip);
  EXPECT_EQ(f.solver.pic_fraction, 0.05);
}

TEST(TransferKeys, OutOfRangeOrMisplacedKeysNameTheKey) {
  for (const std::string& lines :
       {std::string("pic_fraction = 1.5"), std::string("pic_fraction = -0.1"),
        std::string("pic_fraction = nan"), std::string("transfer = \"xpic\"\npic_fraction = 0.5"),
        std::string("transfer = \"fmpm\"\npic_fraction = 0.2"),
        std::string("transfer = \"apic\"\npic_fraction = 0.5")}) {
    const std::string text = solver_with(lines);
    expect_names(error_of(text), line_of(text, "pic_fraction"), "solver.pic_fraction");
  }
  for (const std::string& lines :
       {std::string("transfer = \"xpic\"\nxpic_order = 0"),
        std::string("transfer = \"xpic\"\nxpic_order = 33"),
        std::string("transfer = \"xpic\"\nxpic_order = 2.5"), std::string("xpic_order = 3")}) {
    const std::string text = solver_with(lines);
    expect_names(error_of(text), line_of(text, "xpic_order"), "solver.xpic_order");
  }
  for (const std::string& lines :
       {std::string("transfer = \"fmpm\"\nfmpm_order = 0"),
        std::string("transfer = \"fmpm\"\nfmpm_order = 33"),
        std::string("transfer = \"fmpm\"\nfmpm_order = 1.5"), std::string("fmpm_order = 3"),
        std::string("transfer = \"xpic\"\nfmpm_order = 3")}) {
    const std::string text = solver_with(lines);
    expect_names(error_of(text), line_of(text, "fmpm_order"), "solver.fmpm_order");
  }
  for (const std::string& lines :
       {std::string("transfer = \"fmpm\"\nfilter_every = 0"),
        std::string("transfer = \"xpic\"\nfilter_every = -3"),
        std::string("transfer = \"fmpm\"\nfilter_every = 2.5"), std::string("filter_every = 5"),
        std::string("transfer = \"apic\"\nfilter_every = 5"),
        std::string("pic_fraction = 0.05\nfilter_every = 5")}) {
    const std::string text = solver_with(lines);
    expect_names(error_of(text), line_of(text, "filter_every"), "solver.filter_every");
  }
  // APIC's C_p jumps where a point crosses a cell face with linear shapes.
  const std::string linear = solver_with("shape = \"linear\"\ntransfer = \"apic\"");
  expect_names(error_of(linear), line_of(linear, "transfer"), "solver.transfer");
  const std::string unknown = solver_with("transfer = \"xpik\"");
  const std::string msg = error_of(unknown);
  expect_names(msg, line_of(unknown, "transfer"), "solver.transfer");
  EXPECT_NE(msg.find("xpic"), std::string::npos) << msg;
}

}  // namespace
}  // namespace shatter::scene
