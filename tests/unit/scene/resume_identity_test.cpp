// A run of N steps and a run of N/2 steps + checkpoint + a new Simulation from the checkpoint +
// N/2 steps end bitwise identical (DESIGN.md: "a restart continues bit for bit").

#include <gtest/gtest.h>

#include <cstring>
#include <string>

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

void resume_matches(const std::string& text) {
  constexpr int kSteps = 40;
  test::ScratchDir dir;
  const scene::Scene s = scene::parse_scene(text, "resume.toml");

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

// The scene with another [solver] transfer (lines added after symmetry_plane).
std::string with_transfer(const std::string& lines) {
  std::string text = kScene;
  const std::string anchor = "symmetry_plane = \"z\"\n";
  text.insert(text.find(anchor) + anchor.size(), lines);
  return text;
}

TEST(ResumeIdentity, CheckpointHalfwayAndResumeMatchesAnUninterruptedRunBitwise) {
  resume_matches(kScene);
}

// r-z (solver.geometry = "axisymmetric", issue 31): a head-on impact whose target carries
// Grady-Kipp damage with the ring-weighted flaws, resumed from a checkpoint: the geometry is in
// the checkpoint's scene text, the rings' volumes and flaws in its columns.
TEST(ResumeIdentity, AxisymmetricWithDamageResumesBitwise) {
  resume_matches(R"(
[solver]
geometry = "axisymmetric"
shape = "bspline2"
cell_size = 1.0e-3
end_time = 1.0
[domain]
lo = [0.0, -0.03, -0.03]
hi = [0.03, 0.03, 0.02]
boundary = "outflow"
[body.target]
shape = "sphere"
centre = [0.0, 0.0, -0.012]
radius = 0.012
material = { name = "basalt", yield = 30.0e6 }
[body.target.damage]
model = "grady_kipp"
weibull_m = 8.5
weibull_k = 3.0e39
total_flaws = 1.0e10
[body.projectile]
shape = "sphere"
radius = 4.0e-3
material = "nylon"
[impact]
projectile = "projectile"
target = "target"
speed = 3200.0
angle = 0.0
direction = [0.0, 0.0, -1.0]
[output]
fragments = false
)");
}

// Periodic filtering (solver.filter_every): the phase comes from Clock::step, which the
// checkpoint carries, so a resume at step 20 with N = 3 filters at 21, 24, ... as the straight
// run does (a phase restarted at the resume would filter at 23, 26, ... and differ).
TEST(ResumeIdentity, PeriodicXpicAndFmpmResumeBitwise) {
  resume_matches(with_transfer("transfer = \"xpic\"\nxpic_order = 3\nfilter_every = 3\n"));
  resume_matches(with_transfer("transfer = \"fmpm\"\nfmpm_order = 3\nfilter_every = 3\n"));
}

// filter_every = N is plain FLIP on the steps between filtering steps, bitwise: steps 1-3 of
// N = 4 equal FLIP's from the same start, step 4 (filtered) does not, and step 5 taken from the
// state after step 4 equals a FLIP step from that same state (checkpointed after step 4 and
// resumed with transfer = "flip"). Bitwise, no tolerance: on those steps the engine takes
// FLIP's branches and nothing else.
TEST(PeriodicFilter, OffStepsAreFlipBitwise) {
  for (const std::string& lines : {std::string("transfer = \"xpic\"\nxpic_order = 3\n"),
                                   std::string("transfer = \"fmpm\"\nfmpm_order = 3\n")}) {
    test::ScratchDir dir;
    const scene::Scene periodic =
        scene::parse_scene(with_transfer(lines + "filter_every = 4\n"), "periodic.toml");
    const scene::Scene flip = scene::parse_scene(kScene, "flip.toml");
    scene::BuiltScene bp = scene::build(periodic), bf = scene::build(flip);
    Simulation p(periodic.solver, std::move(bp.particles), bp.materials, 1);
    Simulation f(flip.solver, std::move(bf.particles), bf.materials, 1);
    for (int k = 0; k < 3; ++k) {
      p.step();
      f.step();
    }
    expect_bitwise_equal(f.particles(), p.particles());
    p.step();
    f.step();
    const auto a = p.particles().col(Field::vx), b = f.particles().col(Field::vx);
    EXPECT_NE(std::memcmp(a.data(), b.data(), a.size_bytes()), 0) << lines;  // step 4 filtered

    RunState state;
    state.clock = p.clock();
    state.energy = p.energy();
    state.scene_text = flip.resolved;
    write_checkpoint(dir / "c.h5", p.particles(), state);
    const Checkpoint c = read_checkpoint(dir / "c.h5");
    Simulation r(flip.solver, ParticleStore(c.particles), scene::build_materials(flip), 1);
    restore_columns(r.particles(), c.particles);
    r.restore(c.state.clock, c.state.energy);
    p.step();
    r.step();
    EXPECT_EQ(r.energy().kinetic, p.energy().kinetic) << lines;
    expect_bitwise_equal(p.particles(), r.particles());
  }
}

}  // namespace
}  // namespace shatter::io
