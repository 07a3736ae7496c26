#include "shatter/io/checkpoint.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <string>

#include "sample_store.hpp"
#include "scratch_dir.hpp"
#include "shatter/io/snapshot.hpp"

namespace shatter::io {
namespace {

using test::sample_store;
using test::ScratchDir;

RunState sample_state() {
  RunState s;
  s.clock = {1.0 / 3.0e5, 1.7e-9 / 3.0, 2.2e-9 / 7.0, 123456789};
  s.energy.kinetic = 1.0 / 7.0;
  s.energy.internal = 2.0 / 11.0;
  s.energy.potential = -1e-3 / 13.0;
  s.energy.boundary_work = 1e-9 / 3.0;
  s.energy.outflow = 5e-7 / 9.0;
  s.energy.initial = 0.3333333333333333;
  s.energy.scale = 0.75;
  s.cursor = {4, 4.0e-5, 5.0e-5};
  s.scene_text = "[solver]\ncell_size = 1.6e-3\n# ünïcode survives\n";
  s.program_version = "0.1.0";
  return s;
}

// Bitwise equality of two stores: every registered column, integer ones too, and the groups.
void expect_identical(const ParticleStore& a, const ParticleStore& b) {
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(a.registered(), b.registered());
  ASSERT_EQ(a.groups().size(), b.groups().size());
  for (std::size_t g = 0; g < a.groups().size(); ++g) {
    EXPECT_EQ(a.groups()[g].range.begin, b.groups()[g].range.begin);
    EXPECT_EQ(a.groups()[g].range.end, b.groups()[g].range.end);
    EXPECT_EQ(a.groups()[g].material, b.groups()[g].material);
  }
  for (std::size_t i = 0; i < kFieldCount; ++i) {
    const auto f = static_cast<Field>(i);
    if (!a.has(f)) continue;
    for (std::size_t p = 0; p < a.size(); ++p) ASSERT_EQ(a.col(f)[p], b.col(f)[p]) << name_of(f);
  }
  for (std::size_t i = 0; i < kIFieldCount; ++i) {
    const auto f = static_cast<IField>(i);
    ASSERT_EQ(a.has(f), b.has(f));
    if (!a.has(f)) continue;
    for (std::size_t p = 0; p < a.size(); ++p) ASSERT_EQ(a.col(f)[p], b.col(f)[p]) << name_of(f);
  }
}

void expect_identical(const RunState& a, const RunState& b) {
  EXPECT_EQ(a.clock.time, b.clock.time);
  EXPECT_EQ(a.clock.dt, b.clock.dt);
  EXPECT_EQ(a.clock.dt_prev, b.clock.dt_prev);
  EXPECT_EQ(a.clock.step, b.clock.step);
  EXPECT_EQ(a.energy.kinetic, b.energy.kinetic);
  EXPECT_EQ(a.energy.internal, b.energy.internal);
  EXPECT_EQ(a.energy.potential, b.energy.potential);
  EXPECT_EQ(a.energy.boundary_work, b.energy.boundary_work);
  EXPECT_EQ(a.energy.outflow, b.energy.outflow);
  EXPECT_EQ(a.energy.initial, b.energy.initial);
  EXPECT_EQ(a.energy.scale, b.energy.scale);
  EXPECT_EQ(a.cursor.next_snapshot, b.cursor.next_snapshot);
  EXPECT_EQ(a.cursor.next_snapshot_time, b.cursor.next_snapshot_time);
  EXPECT_EQ(a.cursor.next_checkpoint_time, b.cursor.next_checkpoint_time);
  EXPECT_EQ(a.scene_text, b.scene_text);
  EXPECT_EQ(a.program_version, b.program_version);
}

TEST(Checkpoint, RoundTripIsBitwise) {
  ScratchDir dir;
  ParticleStore store = sample_store();
  store.require(IField::fragment);  // an integer column the snapshot selection would not hold
  store.col(IField::fragment)[3] = -1;
  const RunState state = sample_state();
  write_checkpoint(dir / "c.h5", store, state);
  const Checkpoint back = read_checkpoint(dir / "c.h5");
  expect_identical(store, back.particles);
  expect_identical(state, back.state);
}

TEST(Checkpoint, SceneTextLargerThanAnAttributeFits) {
  ScratchDir dir;
  RunState state = sample_state();
  state.scene_text.assign(200000, 'x');  // HDF5 attributes are limited to 64 KiB
  write_checkpoint(dir / "c.h5", sample_store(), state);
  EXPECT_EQ(read_checkpoint(dir / "c.h5").state.scene_text.size(), 200000u);
}

TEST(Checkpoint, FailureDuringWriteKeepsThePreviousCheckpoint) {
  ScratchDir dir;
  const ParticleStore old_store = sample_store();
  const RunState old_state = sample_state();
  write_checkpoint(dir / "c.h5", old_store, old_state);

  RunState new_state = old_state;
  new_state.clock.step += 1000;
  const auto abort_midway = [](std::string_view dataset) {
    if (dataset == "vx") throw std::runtime_error("disk full (simulated)");
  };
  EXPECT_THROW(write_checkpoint(dir / "c.h5", sample_store(50, 50), new_state, abort_midway),
               std::runtime_error);

  const Checkpoint back = read_checkpoint(dir / "c.h5");
  expect_identical(old_store, back.particles);
  expect_identical(old_state, back.state);
  EXPECT_FALSE(std::filesystem::exists(dir / "c.h5.tmp"));
}

TEST(Checkpoint, ProcessKilledDuringWriteKeepsThePreviousCheckpoint) {
  // "fast" forks without re-running the test, so the child writes into this test's directory.
  GTEST_FLAG_SET(death_test_style, "fast");
  ScratchDir dir;
  const ParticleStore old_store = sample_store();
  const RunState old_state = sample_state();
  write_checkpoint(dir / "c.h5", old_store, old_state);

  // The child dies without unwinding or closing anything, as on a crash or SIGKILL, halfway
  // through the particle columns.
  EXPECT_EXIT(write_checkpoint(dir / "c.h5", sample_store(3000, 3000), sample_state(),
                               [](std::string_view dataset) {
                                 if (dataset == "vy") std::_Exit(17);
                               }),
              ::testing::ExitedWithCode(17), "");

  ASSERT_TRUE(std::filesystem::exists(dir / "c.h5.tmp")) << "the crash left its partial file";
  const Checkpoint back = read_checkpoint(dir / "c.h5");
  expect_identical(old_store, back.particles);
  expect_identical(old_state, back.state);

  // The partial temporary file does not hinder the next checkpoint.
  RunState next = old_state;
  next.clock.step = 7;
  write_checkpoint(dir / "c.h5", old_store, next);
  EXPECT_EQ(read_checkpoint(dir / "c.h5").state.clock.step, 7u);
  EXPECT_FALSE(std::filesystem::exists(dir / "c.h5.tmp"));
}

TEST(Checkpoint, TruncatedCheckpointIsAnErrorNamingTheFile) {
  ScratchDir dir;
  write_checkpoint(dir / "c.h5", sample_store(4000, 10), sample_state());
  std::filesystem::resize_file(dir / "c.h5", std::filesystem::file_size(dir / "c.h5") / 3);
  try {
    read_checkpoint(dir / "c.h5");
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("c.h5"), std::string::npos) << e.what();
  }
}

TEST(Checkpoint, GarbageFileIsAnError) {
  ScratchDir dir;
  std::ofstream(dir / "c.h5") << "not hdf5 at all";
  EXPECT_THROW(read_checkpoint(dir / "c.h5"), std::runtime_error);
}

TEST(Checkpoint, SnapshotIsNotAcceptedAsACheckpoint) {
  ScratchDir dir;
  const ParticleStore store = sample_store();
  write_snapshot(dir / "s.h5", store, {}, all_columns(store));
  try {
    read_checkpoint(dir / "s.h5");
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("not a shatter checkpoint"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace shatter::io
