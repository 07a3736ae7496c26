// Integrity of the attributes readers use (issue 33, items 2 and 3): a snapshot's time, step and
// symmetry axis and a checkpoint's format_version are sealed by a CRC-32 (h5::seal_attrs); a
// flipped byte in the file or a changed value is refused naming the file. Older files without
// the seal: snapshots are read (header.checksummed false, the CLI warns), checkpoints of format
// 1 and 2 are read as before unless they carry what a later format adds.

#include <gtest/gtest.h>
#include <hdf5.h>

#include <cstring>
#include <fstream>
#include <string>

#include "sample_store.hpp"
#include "scratch_dir.hpp"
#include "shatter/io/checkpoint.hpp"
#include "shatter/io/snapshot.hpp"

namespace shatter::io {
namespace {

using test::sample_store;
using test::ScratchDir;

// A time whose 8 bytes occur once in the file (not a round number).
constexpr double kTime = 1.234567890123e-6;

std::string slurp(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), {}};
}

// Inverts one byte of the first occurrence of `pattern` in the file, as a disk would.
void flip_in_file(const std::filesystem::path& file, const std::string& pattern, int byte) {
  const std::string data = slurp(file);
  const auto at = data.find(pattern);
  ASSERT_NE(at, std::string::npos);
  ASSERT_EQ(data.find(pattern, at + 1), std::string::npos) << "pattern not unique";
  std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
  f.seekp(static_cast<std::streamoff>(at + static_cast<std::size_t>(byte)));
  f.put(static_cast<char>(data[at + static_cast<std::size_t>(byte)] ^ 0x01));
}

void set_u64(const std::filesystem::path& file, const char* name, std::uint64_t v) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  const hid_t a = H5Aopen(f, name, H5P_DEFAULT);
  H5Awrite(a, H5T_NATIVE_UINT64, &v);
  H5Aclose(a);
  H5Fclose(f);
}

template <class Read>
std::string error_of(Read read) {
  try {
    read();
  } catch (const std::exception& e) {
    return e.what();
  }
  return {};
}

std::filesystem::path snapshot_in(const ScratchDir& dir) {
  const ParticleStore store = sample_store();
  write_snapshot(dir / "s.h5", store, {kTime, 3, "test", 2}, all_columns(store));
  return dir / "s.h5";
}

TEST(HeaderIntegrity, SnapshotHeaderRoundTripsVerified) {
  ScratchDir dir;
  const Snapshot s = read_snapshot(snapshot_in(dir));
  EXPECT_TRUE(s.header.checksummed);
  EXPECT_EQ(s.header.time, kTime);
  EXPECT_EQ(s.header.symmetry_axis, 2);
  EXPECT_TRUE(inspect_snapshot(dir / "s.h5").header.checksummed);
}

TEST(HeaderIntegrity, FlippedTimeByteInASnapshotIsRefused) {
  ScratchDir dir;
  const auto file = snapshot_in(dir);
  std::string bits(sizeof kTime, '\0');
  std::memcpy(bits.data(), &kTime, sizeof kTime);
  flip_in_file(file, bits, 3);
  const std::string msg = error_of([&] { read_snapshot(file); });
  EXPECT_NE(msg.find("attributes of '/'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("are corrupt"), std::string::npos) << msg;
  EXPECT_NE(msg.find("s.h5"), std::string::npos) << msg;
  EXPECT_NE(error_of([&] { inspect_snapshot(file); }).find("are corrupt"), std::string::npos);
}

TEST(HeaderIntegrity, ChangedSymmetryAxisIsRefused) {
  // The case: one changed byte in symmetry_axis doubled the fragment mass, exit 0.
  ScratchDir dir;
  const auto file = snapshot_in(dir);
  set_u64(file, "symmetry_axis", 0);  // stored shifted by one: "no symmetry plane"
  EXPECT_NE(error_of([&] { read_snapshot(file); }).find("are corrupt"), std::string::npos);
}

TEST(HeaderIntegrity, SnapshotWithItsSealRemovedIsRefused) {
  ScratchDir dir;
  const auto file = snapshot_in(dir);
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  H5Adelete(f, "attributes_crc32");
  H5Adelete(f, "attributes_covered");
  H5Fclose(f);
  EXPECT_NE(error_of([&] { read_snapshot(file); }).find("no checksum"), std::string::npos);
}

TEST(HeaderIntegrity, OlderSnapshotIsReadUnverified) {
  // A snapshot written before format_version and the seal: read, flagged for a warning.
  ScratchDir dir;
  const auto file = snapshot_in(dir);
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  for (const char* a : {"attributes_crc32", "attributes_covered", "format_version"}) {
    H5Adelete(f, a);
  }
  H5Fclose(f);
  const Snapshot s = read_snapshot(file);
  EXPECT_FALSE(s.header.checksummed);
  EXPECT_EQ(s.header.time, kTime);
}

RunState state() {
  RunState s;
  s.clock = {2.0e-6, 1.0e-9, 1.1e-9, 42};
  s.dt_first = 3.0e-8;
  s.internal_next = 0.5;
  s.cursor = {2, 2.5e-6, 3.0e-6};
  s.scene_text = "[solver]\n";
  s.program_version = "test";
  return s;
}

TEST(HeaderIntegrity, CheckpointFormatVersionIsCovered) {
  // The case: format_version 2 -> 1 switched the verification off and resumed.
  for (const std::uint64_t v : {1, 2, 4}) {
    ScratchDir dir;
    write_checkpoint(dir / "c.h5", sample_store(), state());
    set_u64(dir / "c.h5", "format_version", v);
    const std::string msg = error_of([&] { read_checkpoint(dir / "c.h5"); });
    EXPECT_NE(msg.find("are corrupt"), std::string::npos) << v << ": " << msg;
  }
}

TEST(HeaderIntegrity, FormatTwoCheckpointClaimingFormatOneIsRefused) {
  // A format-2 file (no seal, but state_crc32 and dataset checksums) whose version reads 1.
  ScratchDir dir;
  write_checkpoint(dir / "c.h5", sample_store(), state());
  {
    const hid_t f = H5Fopen((dir / "c.h5").c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    H5Adelete(f, "attributes_crc32");
    H5Adelete(f, "attributes_covered");
    H5Fclose(f);
  }
  set_u64(dir / "c.h5", "format_version", 2);
  EXPECT_NO_THROW(read_checkpoint(dir / "c.h5"));  // format 2 as such is still read
  set_u64(dir / "c.h5", "format_version", 1);
  EXPECT_NE(error_of([&] { read_checkpoint(dir / "c.h5"); }).find("format_version says 1"),
            std::string::npos);
  set_u64(dir / "c.h5", "format_version", 3);
  EXPECT_NE(error_of([&] { read_checkpoint(dir / "c.h5"); }).find("without its attribute checksum"),
            std::string::npos);
}

}  // namespace
}  // namespace shatter::io
