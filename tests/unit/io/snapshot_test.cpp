#include "shatter/io/snapshot.hpp"

#include <gtest/gtest.h>
#include <hdf5.h>

#include <cmath>
#include <fstream>
#include <string>

#include "sample_store.hpp"
#include "scratch_dir.hpp"

namespace shatter::io {
namespace {

using test::sample_store;
using test::ScratchDir;

SnapshotOptions single_precision() {
  SnapshotOptions o;
  o.single_precision = true;
  return o;
}

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
      {"/particles/position", "m"}, {"/particles/velocity", "m/s"}, {"/particles/mass", "kg"},
      {"/particles/rho", "kg/m^3"}, {"/particles/energy", "J/kg"},  {"/particles/damage", "1"},
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

TEST(Snapshot, VectorsAndStressAreTwoDimensionalDatasetsThatReadBackExactly) {
  ScratchDir dir;
  ParticleStore store = sample_store();
  store.require(kStress);
  for (std::size_t p = 0; p < store.size(); ++p) {
    store.col(Field::sxy)[p] = 1.0 / (p + 1.0);
    store.col(Field::szz)[p] = -std::sqrt(p + 2.0);
  }
  write_snapshot(dir / "s.h5", store, {}, all_columns(store));
  const hid_t f = H5Fopen((dir / "s.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  for (const auto& [path, cols] : {std::pair{"/particles/position", 3},
                                   {"/particles/velocity", 3},
                                   {"/particles/stress", 6}}) {
    const hid_t d = H5Dopen2(f, path, H5P_DEFAULT);
    ASSERT_GE(d, 0) << path;
    const hid_t space = H5Dget_space(d);
    hsize_t dims[2] = {0, 0};
    EXPECT_EQ(H5Sget_simple_extent_dims(space, dims, nullptr), 2) << path;
    EXPECT_EQ(dims[0], store.size());
    EXPECT_EQ(dims[1], static_cast<hsize_t>(cols));
    H5Sclose(space);
    H5Dclose(d);
  }
  EXPECT_LT(H5Lexists(f, "/particles/x", H5P_DEFAULT), 1);
  H5Fclose(f);
  // Exact: binary64 values, only rearranged.
  const Snapshot back = read_snapshot(dir / "s.h5");
  for (Field c : all_columns(store).fields) {
    for (std::size_t p = 0; p < store.size(); ++p) {
      EXPECT_EQ(back.particles.col(c)[p], store.col(c)[p]) << name_of(c) << " " << p;
    }
  }
}

TEST(Snapshot, BodyAndMaterialNamesRoundTrip) {
  ScratchDir dir;
  const ParticleStore store = sample_store();
  SnapshotOptions o;
  o.body_names = {"target", "projectile"};
  o.material_names = {"basalt", "nylon_6_6"};
  write_snapshot(dir / "s.h5", store, {}, all_columns(store), o);
  const Snapshot back = read_snapshot(dir / "s.h5");
  EXPECT_EQ(back.body_names, o.body_names);
  EXPECT_EQ(back.material_names, o.material_names);
}

TEST(Snapshot, SinglePrecisionStoresBinary32AndReadsBackRounded) {
  // Each value comes back as its nearest binary32: relative error at most 2^-24.
  ScratchDir dir;
  const ParticleStore store = sample_store();
  write_snapshot(dir / "s.h5", store, {}, all_columns(store), single_precision());
  const SnapshotInfo info = inspect_snapshot(dir / "s.h5");
  for (const SnapshotDataset& d : info.datasets) {
    EXPECT_EQ(d.bytes, d.real ? 4u : 8u) << d.name;
  }
  const Snapshot back = read_snapshot(dir / "s.h5");
  for (Field c : all_columns(store).fields) {
    for (std::size_t p = 0; p < store.size(); ++p) {
      const double v = store.col(c)[p];
      EXPECT_EQ(back.particles.col(c)[p], static_cast<double>(static_cast<float>(v))) << name_of(c);
      EXPECT_LE(std::abs(back.particles.col(c)[p] - v), std::ldexp(std::abs(v), -24));
    }
  }
  EXPECT_EQ(back.particles.col(IField::id)[3], store.col(IField::id)[3]);
}

}  // namespace
}  // namespace shatter::io
