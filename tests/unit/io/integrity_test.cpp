// Integrity of checkpoints and snapshots (issue 14, item 4): every dataset carries a CRC-32 of its
// values; a file whose bytes changed after it was written is refused with a message naming the
// file and the dataset. Bytes are flipped in the file itself, at the dataset's storage offset as
// HDF5 reports it, as a disk or a copy would corrupt them.

#include <gtest/gtest.h>
#include <hdf5.h>

#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "sample_store.hpp"
#include "scratch_dir.hpp"
#include "shatter/io/checkpoint.hpp"
#include "shatter/io/snapshot.hpp"

namespace shatter::io {
namespace {

using test::sample_store;
using test::ScratchDir;

RunState state() {
  RunState s;
  s.clock = {2.0e-6, 1.0e-9, 1.1e-9, 42};
  s.energy.kinetic = 3.0;
  s.energy.internal = 1.0 / 3.0;
  s.internal_next = 0.1 + 0.2;  // not a round number: the exact bits must come back
  s.dt_first = 3.0e-8;
  s.cursor = {2, 2.5e-6, 3.0e-6};
  s.scene_text = "[solver]\ncell_size = 1e-3\n";
  s.program_version = "test";
  return s;
}

// File offset of a contiguous dataset's values.
haddr_t offset_of(const std::filesystem::path& file, const char* dataset) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t d = H5Dopen2(f, dataset, H5P_DEFAULT);
  const haddr_t at = H5Dget_offset(d);
  H5Dclose(d);
  H5Fclose(f);
  return at;
}

// Inverts `count` bytes of the file from `at`.
void flip(const std::filesystem::path& file, haddr_t at, int count) {
  std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
  for (int i = 0; i < count; ++i) {
    f.seekg(static_cast<std::streamoff>(at) + i);
    const int c = f.get();
    f.seekp(static_cast<std::streamoff>(at) + i);
    f.put(static_cast<char>(c ^ 0xFF));
  }
}

std::string error_reading_checkpoint(const std::filesystem::path& file) {
  try {
    read_checkpoint(file);
  } catch (const std::exception& e) {
    return e.what();
  }
  return {};
}

TEST(Integrity, CheckpointRoundTripKeepsInternalNextAndFirstStep) {
  ScratchDir dir;
  write_checkpoint(dir / "c.h5", sample_store(), state());
  const Checkpoint c = read_checkpoint(dir / "c.h5");
  EXPECT_EQ(c.state.internal_next, 0.1 + 0.2);  // bitwise
  EXPECT_EQ(c.state.dt_first, 3.0e-8);
}

TEST(Integrity, FlippedBytesInEveryCheckpointDatasetAreRefusedNamingIt) {
  // One byte is enough: CRC-32 detects every error burst up to 32 bits.
  for (const char* dataset :
       {"/particles/x", "/particles/energy", "/particles/id", "/groups/begin", "/scene"}) {
    ScratchDir dir;
    write_checkpoint(dir / "c.h5", sample_store(), state());
    flip(dir / "c.h5", offset_of(dir / "c.h5", dataset), 1);
    const std::string msg = error_reading_checkpoint(dir / "c.h5");
    EXPECT_NE(msg.find(std::string("'") + dataset + "' is corrupt"), std::string::npos)
        << dataset << ": " << msg;
    EXPECT_NE(msg.find("c.h5"), std::string::npos) << msg;
  }
}

TEST(Integrity, SixtyFourFlippedBytesAreRefused) {
  // The case: 64 bytes of a data array flipped, previously resumed silently.
  ScratchDir dir;
  write_checkpoint(dir / "c.h5", sample_store(8, 8), state());
  flip(dir / "c.h5", offset_of(dir / "c.h5", "/particles/vx"), 64);
  EXPECT_NE(error_reading_checkpoint(dir / "c.h5").find("'/particles/vx' is corrupt"),
            std::string::npos);
}

TEST(Integrity, ChangedClockAttributeIsRefused) {
  // The clock, energy and schedule are attributes; state_crc32 covers them.
  ScratchDir dir;
  write_checkpoint(dir / "c.h5", sample_store(), state());
  {
    const hid_t f = H5Fopen((dir / "c.h5").c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    const hid_t g = H5Gopen2(f, "clock", H5P_DEFAULT);
    const hid_t a = H5Aopen(g, "time", H5P_DEFAULT);
    const double t = 2.5e-6;
    H5Awrite(a, H5T_NATIVE_DOUBLE, &t);
    H5Aclose(a);
    H5Gclose(g);
    H5Fclose(f);
  }
  EXPECT_NE(error_reading_checkpoint(dir / "c.h5").find("attributes are corrupt"),
            std::string::npos);
}

TEST(Integrity, RemovedChecksumIsRefused) {
  // A checkpoint of format 2 must carry a checksum on every dataset.
  ScratchDir dir;
  write_checkpoint(dir / "c.h5", sample_store(), state());
  {
    const hid_t f = H5Fopen((dir / "c.h5").c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    const hid_t d = H5Dopen2(f, "/particles/mass", H5P_DEFAULT);
    H5Adelete(d, "crc32");
    H5Dclose(d);
    H5Fclose(f);
  }
  EXPECT_NE(error_reading_checkpoint(dir / "c.h5").find("'/particles/mass' has no checksum"),
            std::string::npos);
}

TEST(Integrity, CorruptSnapshotIsRefusedNamingTheDataset) {
  ScratchDir dir;
  const ParticleStore store = sample_store();
  write_snapshot(dir / "s.h5", store, {1e-6, 3, "test"}, all_columns(store));
  EXPECT_NO_THROW(read_snapshot(dir / "s.h5"));
  // Snapshot datasets are deflated, so flipped file bytes would trip zlib first: change the
  // values through HDF5 instead (a corruption the compression layer cannot see) and keep the
  // stored checksum.
  {
    const hid_t f = H5Fopen((dir / "s.h5").c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    const hid_t d = H5Dopen2(f, "/particles/rho", H5P_DEFAULT);
    std::vector<double> rho(store.size());
    ASSERT_GE(H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, rho.data()), 0);
    rho[2] += 1.0;
    ASSERT_GE(H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, rho.data()), 0);
    H5Dclose(d);
    H5Fclose(f);
  }
  try {
    read_snapshot(dir / "s.h5");
    ADD_FAILURE() << "a corrupt snapshot was read";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("'/particles/rho' is corrupt"), std::string::npos)
        << e.what();
  }
}

TEST(Integrity, SameDataGiveTheSameBytes) {
  // No wall-clock times in the files: a resumed run can reproduce an uninterrupted run's files
  // byte for byte (docs/reliability.md).
  ScratchDir dir;
  const ParticleStore store = sample_store();
  write_snapshot(dir / "a.h5", store, {1e-6, 3, "test"}, all_columns(store));
  sleep(1);  // object header times have a resolution of one second
  write_snapshot(dir / "b.h5", store, {1e-6, 3, "test"}, all_columns(store));
  std::ifstream a(dir / "a.h5", std::ios::binary), b(dir / "b.h5", std::ios::binary);
  const std::string sa((std::istreambuf_iterator<char>(a)), {});
  const std::string sb((std::istreambuf_iterator<char>(b)), {});
  EXPECT_EQ(sa.size(), sb.size());
  EXPECT_TRUE(sa == sb);
}

}  // namespace
}  // namespace shatter::io
