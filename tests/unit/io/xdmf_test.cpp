#include "shatter/io/xdmf.hpp"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <cstdint>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "io/h5.hpp"
#include "sample_store.hpp"
#include "scratch_dir.hpp"
#include "shatter/io/snapshot.hpp"

namespace shatter::io {
namespace {

using test::sample_store;
using test::ScratchDir;

SnapshotOptions single_precision() {
  SnapshotOptions o;
  o.single_precision = true;
  return o;
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto pos = text.find(what); pos != std::string::npos; pos = text.find(what, pos + 1)) ++n;
  return n;
}

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

TEST(Xdmf, SeriesListsEverySnapshotAsATimeStepWithEveryColumn) {
  ScratchDir dir;
  std::filesystem::create_directories(dir / "snapshots");
  ParticleStore store = sample_store();
  store.require(kStress);
  for (Field f : {Field::sxx, Field::syy, Field::szz, Field::sxy, Field::syz, Field::sxz}) {
    store.col(f)[1] = 1.0 + static_cast<double>(f);
  }
  const ColumnSelection cols = all_columns(store);
  XdmfSeries series(dir / "particles.xmf");
  for (int k = 0; k < 3; ++k) {
    const auto file = dir / "snapshots" / fmt::format("snapshot_{:06d}.h5", k);
    write_snapshot(file, store, {1e-6 * k, static_cast<std::uint64_t>(10 * k), "v"}, cols);
    series.add(file);
  }
  const std::string doc = slurp(dir / "particles.xmf");

  EXPECT_EQ(count(doc, "CollectionType=\"Temporal\""), 1u);
  EXPECT_EQ(count(doc, "<Time Value="), 3u);
  EXPECT_NE(doc.find("<Time Value=\"2e-06\" />"), std::string::npos) << doc;
  EXPECT_EQ(count(doc, "TopologyType=\"Polyvertex\" NumberOfElements=\"8\" NodesPerElement=\"1\">"),
            3u);
  // Explicit vertex cells (ParaView builds none without them), all from the one shared file.
  EXPECT_EQ(count(doc,
                  "<DataItem Dimensions=\"8 1\" NumberType=\"Int\" Precision=\"8\" "
                  "Format=\"HDF\">particles_cells.h5:/cells/n8</DataItem>"),
            3u)
      << doc;
  // Positions as one N x 3 dataset (XYZ: ParaView's Xdmf3 reader ignores X_Y_Z), velocity a
  // vector, stress a Tensor6; every other column a scalar.
  EXPECT_EQ(count(doc, "GeometryType=\"XYZ\""), 3u);
  EXPECT_NE(doc.find("<DataItem Dimensions=\"8 3\" NumberType=\"Float\" Precision=\"8\" "
                     "Format=\"HDF\">snapshots/snapshot_000001.h5:/particles/position"),
            std::string::npos)
      << doc;
  EXPECT_EQ(count(doc, "<Attribute Name=\"velocity\" AttributeType=\"Vector\""), 3u);
  EXPECT_EQ(count(doc, "<Attribute Name=\"stress\" AttributeType=\"Tensor6\""), 3u);
  EXPECT_NE(doc.find("<DataItem Dimensions=\"8 6\""), std::string::npos);
  for (const char* name : {"mass", "volume0", "rho", "damage", "energy", "id", "body"}) {
    EXPECT_EQ(count(doc, std::string("<Attribute Name=\"") + name + "\" AttributeType=\"Scalar\""),
              3u)
        << name;
  }
  EXPECT_EQ(count(doc, "<Attribute "), 3u * 9u);  // velocity, stress and the 7 scalars
  EXPECT_NE(doc.find("NumberType=\"Int\" Precision=\"8\" Format=\"HDF\">"
                     "snapshots/snapshot_000002.h5:/particles/id"),
            std::string::npos);
  // Units beside the attributes, not inside them (meshio reads an Attribute's only child).
  EXPECT_EQ(count(doc, "<Information Name=\"units:velocity\" Value=\"m/s\" />"), 3u) << doc;
  EXPECT_EQ(count(doc,
                  "<Attribute Name=\"velocity\" AttributeType=\"Vector\" "
                  "Center=\"Node\">\n          <DataItem"),
            3u);
  // Balanced elements: a truncated or malformed document would not be.
  EXPECT_EQ(count(doc, "<Grid "), 4u);
  EXPECT_EQ(count(doc, "</Grid>"), 4u);
  EXPECT_EQ(count(doc, "<Attribute "), count(doc, "</Attribute>"));
  EXPECT_NE(doc.find("</Xdmf>"), std::string::npos);
}

TEST(Xdmf, RebuildKeepsSnapshotsUpToTheResumeTimeInTimeOrder) {
  ScratchDir dir;
  const ParticleStore store = sample_store();
  std::vector<std::filesystem::path> files;
  for (int k : {2, 0, 1}) {
    files.push_back(dir / fmt::format("s{}.h5", k));
    write_snapshot(files.back(), store, {1.0 * k, 0, ""}, all_columns(store));
  }
  XdmfSeries series(dir / "p.xmf");
  series.rebuild(files, 1.0);
  ASSERT_EQ(series.entries().size(), 2u);
  EXPECT_EQ(series.entries()[0].file, "s0.h5");
  EXPECT_EQ(series.entries()[1].file, "s1.h5");
}

TEST(Xdmf, SnapshotWithoutPositionsCannotBeDescribed) {
  XdmfEntry e;
  e.file = "a.h5";
  e.particles = 1;
  for (const char* name : {"x", "y", "damage"}) {
    SnapshotDataset d;
    d.name = name;
    e.datasets.push_back(d);
  }
  EXPECT_THROW(xdmf_document({e}, "c.h5"), std::invalid_argument);
}

TEST(Xdmf, SinglePrecisionSnapshotsAreDescribedAsFourByteFloats) {
  ScratchDir dir;
  const ParticleStore store = sample_store();
  write_snapshot(dir / "s.h5", store, {}, all_columns(store), single_precision());
  XdmfSeries series(dir / "p.xmf");
  series.add(dir / "s.h5");
  const std::string doc = slurp(dir / "p.xmf");
  EXPECT_NE(doc.find("Dimensions=\"8 3\" NumberType=\"Float\" Precision=\"4\""), std::string::npos)
      << doc;
  // Integer columns stay 64-bit.
  EXPECT_NE(doc.find("NumberType=\"Int\" Precision=\"8\" Format=\"HDF\">s.h5:/particles/id"),
            std::string::npos);
}

TEST(Xdmf, CellsFileHoldsZeroToNMinusOneWrittenOncePerParticleCount) {
  ScratchDir dir;
  ParticleStore store = sample_store();
  XdmfSeries series(dir / "p.xmf");
  ASSERT_EQ(series.cells_path(), dir / "p_cells.h5");
  write_snapshot(dir / "a.h5", store, {0.0, 0, ""}, all_columns(store));
  series.add(dir / "a.h5");
  const auto first = std::filesystem::last_write_time(series.cells_path());
  const auto ino = [](const std::filesystem::path& p) {
    struct stat st {};
    EXPECT_EQ(::stat(p.c_str(), &st), 0);
    return st.st_ino;
  };
  const auto inode = ino(series.cells_path());
  write_snapshot(dir / "b.h5", store, {1.0, 1, ""}, all_columns(store));
  series.add(dir / "b.h5");
  // Same particle count: the file is not rewritten (an atomic rewrite would change the inode).
  EXPECT_EQ(ino(series.cells_path()), inode);
  EXPECT_EQ(std::filesystem::last_write_time(series.cells_path()), first);
  {
    h5::Handle f = h5::open_file(series.cells_path());
    EXPECT_EQ(h5::read_ints(f.get(), "cells/n8"),
              (std::vector<std::int64_t>{0, 1, 2, 3, 4, 5, 6, 7}));
  }
  // A snapshot with a different count adds its own connectivity; the old one stays.
  ParticleStore small = sample_store();
  const std::vector<std::uint8_t> drop{1, 0, 0, 1, 0, 1, 0, 0};
  ASSERT_EQ(small.remove_if(drop), 3u);
  write_snapshot(dir / "c.h5", small, {2.0, 2, ""}, all_columns(small));
  series.add(dir / "c.h5");
  h5::Handle f = h5::open_file(series.cells_path());
  EXPECT_EQ(h5::read_ints(f.get(), "cells/n5"), (std::vector<std::int64_t>{0, 1, 2, 3, 4}));
  EXPECT_EQ(h5::read_ints(f.get(), "cells/n8").size(), 8u);
  EXPECT_NE(slurp(dir / "p.xmf").find("p_cells.h5:/cells/n5</DataItem>"), std::string::npos);
}

}  // namespace
}  // namespace shatter::io
