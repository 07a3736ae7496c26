// The porosity output column is derived from the distension when a snapshot is written (issue
// 29): it is not a state column, so it is computed at write time, listed by the file's
// inspection and skipped when the file is read back.

#include <gtest/gtest.h>

#include "sample_store.hpp"
#include "scratch_dir.hpp"
#include "shatter/io/snapshot.hpp"

namespace shatter::io {
namespace {

using test::sample_store;
using test::ScratchDir;

// The sample store with a distension: porous points (alpha >= 1) in group 0, dense points of
// group 1 left at the column's zero fill, as a dense body beside a porous one has them.
ParticleStore porous_store() {
  ParticleStore s = sample_store();
  s.require(Field::distension);
  for (std::size_t p = 0; p < 5; ++p) s.col(Field::distension)[p] = 1.0 + 0.37 * p;
  return s;
}

TEST(DerivedColumns, PorosityIsOneMinusInverseDistensionAndZeroForDensePoints) {
  ScratchDir dir;
  const ParticleStore store = porous_store();
  const auto cols = select_columns({"x", "distension", "porosity"});
  ASSERT_EQ(cols.derived.size(), 1u);
  write_snapshot(dir / "s.h5", store, {}, cols);

  const SnapshotInfo info = inspect_snapshot(dir / "s.h5");
  ASSERT_EQ(info.columns.derived.size(), 1u);
  EXPECT_EQ(info.columns.derived[0], Derived::porosity);

  // The values as the file holds them: exact (the writer's expression, no tolerance needed).
  const std::vector<double> phi = derived_values(store, Derived::porosity);
  for (std::size_t p = 0; p < store.size(); ++p) {
    const double a = store.col(Field::distension)[p];
    EXPECT_EQ(phi[p], p < 5 ? 1.0 - 1.0 / a : 0.0) << "point " << p;
  }
  EXPECT_EQ(phi[0], 0.0);  // alpha = 1: no pores

  // Read back: the distension is restored, the porosity is not a column of the store.
  const Snapshot back = read_snapshot(dir / "s.h5");
  ASSERT_TRUE(back.particles.has(Field::distension));
  EXPECT_EQ(back.particles.col(Field::distension)[3], store.col(Field::distension)[3]);
}

TEST(DerivedColumns, PorosityNeedsTheDistension) {
  const ParticleStore dense = sample_store();
  EXPECT_TRUE(registered_subset(select_columns({"porosity"}), dense).derived.empty());
  EXPECT_TRUE(all_columns(dense).derived.empty());
  EXPECT_EQ(all_columns(porous_store()).derived.size(), 1u);
  EXPECT_EQ(select_columns({"x", "porosity"}).names(), (std::vector<std::string>{"x", "porosity"}));
}

}  // namespace
}  // namespace shatter::io
