#include <gtest/gtest.h>

#include <memory>

#include "shatter/grid/sparse_grid.hpp"
#include "shatter/material/linear_elastic.hpp"
#include "shatter/mpm/simulation.hpp"
#include "support/lattice.hpp"

using namespace shatter;
using Eigen::Vector3d;

namespace {

std::vector<MaterialPtr> elastic() {
  return {std::make_shared<LinearElastic>(1000.0, 1e6, 0.25)};
}

}  // namespace

TEST(SparseGrid, MemoryFollowsActiveBlocksNotTheBoundingBox) {
  // Two small cubes 10 km apart with 1 cm cells: a dense grid would need ~1e18 nodes.
  ParticleStore near, far;
  test::add_box(near, 0, Vector3d(0, 0, 0), Vector3d(0.08, 0.08, 0.08), 0.005, 1000.0);
  test::add_box(far, 0, Vector3d(0, 0, 0), Vector3d(0.08, 0.08, 0.08), 0.005, 1000.0);
  ParticleStore both;
  test::add_box(both, 0, Vector3d(0, 0, 0), Vector3d(0.08, 0.08, 0.08), 0.005, 1000.0);
  test::add_box(both, 0, Vector3d(1e4, 1e4, 1e4), Vector3d(1e4 + 0.08, 1e4 + 0.08, 1e4 + 0.08),
                0.005, 1000.0);
  SolverConfig cfg;
  cfg.cell_size = 0.01;
  Simulation one(cfg, std::move(near), elastic(), 1);
  Simulation two(cfg, std::move(both), elastic(), 1);
  one.step();
  two.step();
  // The second body costs exactly the blocks of the first (same shape, grid-aligned offset).
  EXPECT_EQ(two.active_blocks(), 2 * one.active_blocks());
  EXPECT_LT(two.grid_bytes(), 3 * one.grid_bytes());
}

TEST(SparseGrid, ColoursNeverShareANode) {
  // Owner blocks of one colour write blocks b + {0,1}^3; check those sets are disjoint.
  std::vector<std::uint64_t> keys;
  for (int x = -3; x < 3; ++x) {
    for (int y = -2; y < 2; ++y) {
      for (int z = 0; z < 3; ++z) keys.push_back(SparseGrid::key(x, y, z));
    }
  }
  SparseGrid g;
  ASSERT_TRUE(g.assign(keys));
  EXPECT_FALSE(g.assign(keys));  // unchanged keys: nothing is rebuilt
  for (int c = 0; c < SparseGrid::kColours; ++c) {
    std::vector<int> writers(g.blocks(), 0);
    for (const std::uint32_t b : g.colour(c)) {
      for (int s = 0; s < 8; ++s) ++writers[g.neighbour(b, s)];
    }
    for (const int w : writers) EXPECT_LE(w, 1) << "colour " << c;
  }
}

// assign() skips the rebuild when its input is the last one, read back from the lists it built
// (no copy of the keys and ids): it must rebuild whenever a rebuild would give other lists, and
// skip only when it would give the same ones.
TEST(SparseGrid, RebuildsExactlyWhenTheListsWouldChange) {
  // Two owner blocks, three particles each, ids not in store order.
  const std::vector<std::uint64_t> keys{SparseGrid::key(0, 0, 0), SparseGrid::key(1, 0, 0),
                                        SparseGrid::key(0, 0, 0), SparseGrid::key(1, 0, 0),
                                        SparseGrid::key(0, 0, 0), SparseGrid::key(1, 0, 0)};
  std::vector<std::int64_t> ids{50, 40, 30, 20, 10, 0};
  const auto lists = [](const SparseGrid& g) {
    return std::vector<std::uint32_t>(g.particle_order().begin(), g.particle_order().end());
  };
  SparseGrid g;
  ASSERT_TRUE(g.assign(keys, {}, ids));
  SparseGrid first;
  ASSERT_TRUE(first.assign(keys, {}, ids));
  EXPECT_EQ(lists(g), lists(first));
  EXPECT_FALSE(g.assign(keys, {}, ids));  // same input
  // Other ids that keep every list ascending: a rebuild would give the same lists.
  std::vector<std::int64_t> same_order{9, 8, 7, 6, 5, 4};
  EXPECT_FALSE(g.assign(keys, {}, same_order));
  SparseGrid same;
  ASSERT_TRUE(same.assign(keys, {}, same_order));
  EXPECT_EQ(lists(g), lists(same));
  // Ids that reorder one block's list: rebuilt, as a fresh grid builds it.
  std::vector<std::int64_t> swapped{9, 8, 7, 6, 11, 4};
  EXPECT_TRUE(g.assign(keys, {}, swapped));
  SparseGrid fresh;
  ASSERT_TRUE(fresh.assign(keys, {}, swapped));
  EXPECT_EQ(lists(g), lists(fresh));
  EXPECT_NE(lists(g), lists(first));
  // Equal ids in one block: rebuilt (no unique order to read back).
  std::vector<std::int64_t> tied{9, 8, 9, 6, 11, 4};
  EXPECT_TRUE(g.assign(keys, {}, tied));
  // One key moved: rebuilt; no ids after ids: rebuilt; then unchanged again.
  std::vector<std::uint64_t> moved = keys;
  moved[3] = SparseGrid::key(0, 0, 0);
  EXPECT_TRUE(g.assign(moved, {}, tied));
  EXPECT_TRUE(g.assign(moved));
  EXPECT_FALSE(g.assign(moved));
  EXPECT_TRUE(g.assign(moved, {}, tied));
  // Other bodies: rebuilt.
  const std::vector<std::int64_t> bodies{0, 0, 0, 1, 1, 1}, other{0, 0, 1, 1, 1, 1};
  EXPECT_TRUE(g.assign(moved, bodies, swapped));
  EXPECT_FALSE(g.assign(moved, bodies, swapped));
  EXPECT_TRUE(g.assign(moved, other, swapped));
  SparseGrid fresh_bodies;
  ASSERT_TRUE(fresh_bodies.assign(moved, other, swapped));
  EXPECT_EQ(lists(g), lists(fresh_bodies));
  // Fewer particles: rebuilt.
  moved.pop_back();
  tied.pop_back();
  EXPECT_TRUE(g.assign(moved, {}, tied));
}

TEST(Outflow, MaterialLeavingIsRemovedAndItsEnergyBooked) {
  ParticleStore s;
  test::add_box(s, 0, Vector3d(0, 0, 0), Vector3d(0.2, 0.2, 0.2), 0.025, 1000.0,
                Vector3d(50.0, 0, 0));
  const std::size_t n0 = s.size();
  SolverConfig cfg;
  cfg.cell_size = 0.05;
  cfg.domain.hi.x() = 0.5;
  cfg.domain.faces[1] = BoundaryKind::outflow;
  Simulation sim(cfg, std::move(s), elastic(), 1);
  sim.advance_to(0.0085);  // the front has crossed x = 0.5, the rear has not
  const std::size_t n = sim.particles().size();
  EXPECT_LT(n, n0);
  EXPECT_GT(n, 0u);
  for (const double x : sim.particles().col(Field::x)) EXPECT_LE(x, 0.5);
  // Rigid translation: all energy is kinetic; what left is booked as outflow, so the balance
  // closes to round-off (1e-12 relative).
  EXPECT_GT(sim.energy().outflow, 0.0);
  EXPECT_NEAR(sim.energy().error(), 0.0, 1e-12);
}
