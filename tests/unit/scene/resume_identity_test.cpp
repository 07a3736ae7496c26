// A run of N steps and a run of N/2 steps + checkpoint + a new Simulation from the checkpoint +
// N/2 steps end bitwise identical (DESIGN.md: "a restart continues bit for bit").

#include <gtest/gtest.h>

#include "../io/scratch_dir.hpp"
#include "shatter/io/checkpoint.hpp"
#include "shatter/mpm/simulation.hpp"
#include "shatter/scene/build.hpp"
#include "shatter/scene/scene.hpp"

namespace shatter::io {
namespace {

// A small off-axis impact (elastic-plastic, no damage: the material library decides which damage
// models it offers) with shocks, plasticity, a symmetry plane and outflow faces, so every
// piece of state a step depends on is exercised.
const char* kScene = R"(
[solver]
cell_size = 4.0e-3
end_time = 1.0
symmetry_plane = "z"
[domain]
lo = [-0.05, -0.05, 0.0]
hi = [0.05, 0.05, 0.05]
boundary = "outflow"
[body.target]
shape = "sphere"
centre = [0.0, 0.0, 0.0]
radius = 0.012
material = { name = "basalt", yield = 30.0e6 }
[body.projectile]
shape = "sphere"
radius = 4.0e-3
material = "nylon"
[impact]
projectile = "projectile"
target = "target"
speed = 3200.0
angle = 30.0
)";

void expect_bitwise_equal(const ParticleStore& a, const ParticleStore& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < kFieldCount; ++i) {
    const auto f = static_cast<Field>(i);
    ASSERT_EQ(a.has(f), b.has(f)) << name_of(f);
    if (!a.has(f)) continue;
    std::size_t differ = 0;
    for (std::size_t p = 0; p < a.size(); ++p) differ += a.col(f)[p] != b.col(f)[p] ? 1 : 0;
    EXPECT_EQ(differ, 0u) << "column " << name_of(f);
  }
  for (std::size_t p = 0; p < a.size(); ++p) ASSERT_EQ(a.col(IField::id)[p], b.col(IField::id)[p]);
}

TEST(ResumeIdentity, CheckpointHalfwayAndResumeMatchesAnUninterruptedRunBitwise) {
  constexpr int kSteps = 40;
  test::ScratchDir dir;
  const scene::Scene s = scene::parse_scene(kScene, "resume.toml");

  scene::BuiltScene straight = scene::build(s);
  Simulation a(s.solver, std::move(straight.particles), straight.materials, 2);
  for (int k = 0; k < kSteps; ++k) a.step();

  scene::BuiltScene first = scene::build(s);
  Simulation b(s.solver, std::move(first.particles), first.materials, 2);
  for (int k = 0; k < kSteps / 2; ++k) b.step();
  RunState state;
  state.clock = b.clock();
  state.energy = b.energy();
  state.scene_text = s.resolved;
  write_checkpoint(dir / "c.h5", b.particles(), state);

  // Fresh process state: materials rebuilt from the checkpoint's scene text, another thread count.
  const Checkpoint c = read_checkpoint(dir / "c.h5");
  const scene::Scene s2 = scene::parse_scene(c.state.scene_text, "checkpoint scene");
  Simulation r(s2.solver, ParticleStore(c.particles), scene::build_materials(s2), 1);
  restore_columns(r.particles(), c.particles);
  r.restore(c.state.clock, c.state.energy);
  for (int k = 0; k < kSteps / 2; ++k) r.step();

  EXPECT_EQ(r.clock().step, a.clock().step);
  EXPECT_EQ(r.clock().time, a.clock().time);
  EXPECT_EQ(r.clock().dt, a.clock().dt);
  EXPECT_EQ(r.energy().kinetic, a.energy().kinetic);
  EXPECT_EQ(r.energy().internal, a.energy().internal);
  EXPECT_EQ(r.energy().outflow, a.energy().outflow);
  expect_bitwise_equal(a.particles(), r.particles());
}

}  // namespace
}  // namespace shatter::io
