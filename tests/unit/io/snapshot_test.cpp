#include "shatter/io/snapshot.hpp"

#include <gtest/gtest.h>
#include <hdf5.h>

#include <fstream>
#include <string>

#include "sample_store.hpp"
#include "scratch_dir.hpp"

namespace shatter::io {
namespace {

using test::sample_store;
using test::ScratchDir;

std::string string_attr(hid_t obj, const char* name) {
  const hid_t a = H5Aopen(obj, name, H5P_DEFAULT);
  const hid_t t = H5Aget_type(a);
  std::string s(H5Tget_size(t), '\0');
  H5Aread(a, t, s.data());
  H5Tclose(t);
  H5Aclose(a);
  while (!s.empty() && s.back() == '\0') s.pop_back();
  return s;
}

TEST(Snapshot, RoundTripKeepsEveryValueAndTheGroups) {
  ScratchDir dir;
  const ParticleStore store = sample_store();
  write_snapshot(dir / "s.h5", store, {1.25e-5, 42, "9.9.9"}, all_columns(store));
  const Snapshot back = read_snapshot(dir / "s.h5");

  EXPECT_EQ(back.header.time, 1.25e-5);
  EXPECT_EQ(back.header.step, 42u);
  EXPECT_EQ(back.header.program_version, "9.9.9");
  ASSERT_EQ(back.particles.size(), store.size());
  ASSERT_EQ(back.particles.groups().size(), 2u);
  EXPECT_EQ(back.particles.groups()[1].material, 3);
  EXPECT_EQ(back.particles.groups()[1].range.begin, 5u);
  EXPECT_EQ(back.particles.groups()[1].range.end, 8u);
  for (Field f : all_columns(store).fields) {
    ASSERT_TRUE(back.particles.has(f)) << name_of(f);
    for (std::size_t p = 0; p < store.size(); ++p) {
      EXPECT_EQ(back.particles.col(f)[p], store.col(f)[p]) << name_of(f) << " particle " << p;
    }
  }
  for (std::size_t p = 0; p < store.size(); ++p) {
    EXPECT_EQ(back.particles.col(IField::id)[p], store.col(IField::id)[p]);
    EXPECT_EQ(back.particles.col(IField::body)[p], store.col(IField::body)[p]);
  }
}

TEST(Snapshot, WritesOnlyTheSelectedColumns) {
  ScratchDir dir;
  const ParticleStore store = sample_store();
  write_snapshot(dir / "s.h5", store, {}, select_columns({"x", "y", "z", "damage", "body"}));
  const SnapshotInfo info = inspect_snapshot(dir / "s.h5");
  EXPECT_EQ(info.particles, store.size());
  EXPECT_EQ(info.columns.fields.size(), 4u);
  ASSERT_EQ(info.columns.ifields.size(), 1u);
  EXPECT_EQ(info.columns.ifields[0], IField::body);
}

TEST(Snapshot, FileCarriesTimeStepAndUnitsAttributes) {
  ScratchDir dir;
  const ParticleStore store = sample_store();
  write_snapshot(dir / "s.h5", store, {3.0e-6, 7, "1.0"}, all_columns(store));

  const hid_t f = H5Fopen((dir / "s.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  double t = 0;
  const hid_t ta = H5Aopen(f, "time", H5P_DEFAULT);
  H5Aread(ta, H5T_NATIVE_DOUBLE, &t);
  H5Aclose(ta);
  EXPECT_EQ(t, 3.0e-6);
  std::uint64_t step = 0;
  const hid_t sa = H5Aopen(f, "step", H5P_DEFAULT);
  H5Aread(sa, H5T_NATIVE_UINT64, &step);
  H5Aclose(sa);
  EXPECT_EQ(step, 7u);
  EXPECT_EQ(string_attr(f, "time_units"), "s");

  const std::pair<const char*, const char*> expected[] = {
      {"/particles/x", "m"},        {"/particles/vx", "m/s"},      {"/particles/mass", "kg"},
      {"/particles/rho", "kg/m^3"}, {"/particles/energy", "J/kg"}, {"/particles/damage", "1"},
      {"/particles/id", "1"}};
  for (const auto& [path, units] : expected) {
    const hid_t d = H5Dopen2(f, path, H5P_DEFAULT);
    ASSERT_GE(d, 0) << path;
    EXPECT_EQ(string_attr(d, "units"), units) << path;
    H5Dclose(d);
  }
  H5Fclose(f);
}

TEST(Snapshot, LeavesNoTemporaryFileBehind) {
  ScratchDir dir;
  const ParticleStore store = sample_store();
  write_snapshot(dir / "s.h5", store, {}, all_columns(store));
  EXPECT_TRUE(std::filesystem::exists(dir / "s.h5"));
  EXPECT_FALSE(std::filesystem::exists(dir / "s.h5.tmp"));
}

TEST(Snapshot, MissingFileIsAnErrorNamingIt) {
  ScratchDir dir;
  try {
    read_snapshot(dir / "nope.h5");
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("nope.h5"), std::string::npos) << e.what();
  }
}

TEST(Snapshot, TruncatedFileIsAnErrorNotACrash) {
  ScratchDir dir;
  const ParticleStore store = sample_store(2000, 10);
  write_snapshot(dir / "s.h5", store, {}, all_columns(store));
  std::filesystem::resize_file(dir / "s.h5", std::filesystem::file_size(dir / "s.h5") / 2);
  EXPECT_THROW(read_snapshot(dir / "s.h5"), std::runtime_error);
}

TEST(Snapshot, UnknownColumnNameSuggestsTheClosest) {
  try {
    select_columns({"x", "damgae"});
    FAIL() << "expected an exception";
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("'damgae'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("did you mean 'damage'"), std::string::npos) << msg;
  }
}

TEST(Snapshot, EmptyStoreRoundTrips) {
  ScratchDir dir;
  ParticleStore store;
  store.require(kPosition);
  write_snapshot(dir / "s.h5", store, {}, all_columns(store));
  EXPECT_EQ(read_snapshot(dir / "s.h5").particles.size(), 0u);
}

}  // namespace
}  // namespace shatter::io
