// The MPM step's stage list (src/mpm/step.cpp, App. A.2 of the MPM paper) as a scene builds it:
// the transfer decides the filter and remap stages, the boundaries the outflow stage. Golden
// lists: a change to the step's shape must show here.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "shatter/material/linear_elastic.hpp"
#include "shatter/mpm/simulation.hpp"
#include "support/lattice.hpp"

using namespace shatter;
using Eigen::Vector3d;

namespace {

std::vector<std::string> stages_of(const SolverConfig& cfg) {
  ParticleStore s;
  test::add_box(s, 0, Vector3d::Zero(), Vector3d::Constant(0.2), 0.05, 1000.0, Vector3d::Zero(), 0);
  const Simulation sim(cfg, std::move(s), {std::make_shared<LinearElastic>(1000.0, 1e6, 0.25)}, 1);
  return sim.stage_names();
}

SolverConfig base() {
  SolverConfig cfg;
  cfg.cell_size = 0.1;
  return cfg;
}

TEST(StageList, FlipIsTheMuslStepOfAppendixA2) {
  EXPECT_EQ(stages_of(base()), (std::vector<std::string>{
                                   "sort", "p2g", "grid_update", "g2p", "remap", "remap_velocity",
                                   "constitutive", "advance_positions", "energy", "time_step"}));
}

TEST(StageList, ApicHasNoRemap) {
  SolverConfig cfg = base();
  cfg.transfer = TransferKind::apic;
  EXPECT_EQ(stages_of(cfg),
            (std::vector<std::string>{"sort", "p2g", "grid_update", "g2p", "constitutive",
                                      "advance_positions", "energy", "time_step"}));
}

// Issue 35: the strain and spin increments live in the constitutive stage's chunk buffers; a
// step leaves no column of them in the store.
TEST(StageList, TheIncrementsAreNoStoreColumns) {
  ParticleStore s;
  test::add_box(s, 0, Vector3d::Zero(), Vector3d::Constant(0.2), 0.05, 1000.0,
                Vector3d(10.0, 0.0, 0.0), 0);
  Simulation sim(base(), std::move(s), {std::make_shared<LinearElastic>(1000.0, 1e6, 0.25)}, 1);
  sim.step();
  for (const Field f :
       {Field::deps_xx, Field::deps_yy, Field::deps_zz, Field::deps_xy, Field::deps_yz,
        Field::deps_xz, Field::dspin_xy, Field::dspin_yz, Field::dspin_xz}) {
    EXPECT_FALSE(sim.particles().has(f)) << name_of(f);
  }
  EXPECT_TRUE(sim.particles().has(Field::rho));
}

TEST(StageList, XpicAndFmpmFilterBeforeG2pFromOrderTwo) {
  SolverConfig cfg = base();
  cfg.transfer = TransferKind::xpic;
  cfg.xpic_order = 3;
  // Two passes (m - 1), each its scatter and its nodal update, between grid_update and g2p.
  const std::vector<std::string> xpic = stages_of(cfg);
  ASSERT_GE(xpic.size(), 8u);
  EXPECT_EQ(
      std::vector<std::string>(xpic.begin() + 2, xpic.begin() + 8),
      (std::vector<std::string>{"grid_update", "xpic", "xpic_nodes", "xpic", "xpic_nodes", "g2p"}));
  cfg.xpic_order = 1;  // XPIC(1) is PIC: no extra pass, no filter stage
  EXPECT_EQ(stages_of(cfg).size(), stages_of(base()).size());
  cfg.transfer = TransferKind::fmpm;
  cfg.fmpm_order = 4;
  const std::vector<std::string> fmpm = stages_of(cfg);
  EXPECT_EQ(fmpm[3], "fmpm");
  EXPECT_EQ(fmpm[4], "fmpm_nodes");
  EXPECT_EQ(std::count(fmpm.begin(), fmpm.end(), "fmpm_nodes"), 3) << "k - 1 passes";
}

TEST(StageList, OutflowFacesAddTheOutflowStageAfterThePositions) {
  SolverConfig cfg = base();
  cfg.domain.lo = Vector3d::Constant(-1.0);
  cfg.domain.hi = Vector3d::Constant(1.0);
  cfg.domain.faces[0] = BoundaryKind::outflow;
  const std::vector<std::string> names = stages_of(cfg);
  const auto at = std::find(names.begin(), names.end(), "outflow");
  ASSERT_NE(at, names.end());
  EXPECT_EQ(*(at - 1), "advance_positions");
  EXPECT_EQ(*(at + 1), "energy");
}

}  // namespace
