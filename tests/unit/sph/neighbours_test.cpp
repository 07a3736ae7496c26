// The SPH neighbour search (src/sph/neighbours.cpp) against brute force, on random and clustered
// points with varying h, the fixed list order that makes the gather passes bitwise
// reproducible on any thread count, and lists carried through a renumbering of the points.

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include "shatter/sph/neighbours.hpp"
#include "sph/gather.hpp"

namespace shatter::sph {
namespace {

struct Cloud {
  std::vector<double> x, y, z, h;
  std::size_t size() const { return x.size(); }
  void add(double a, double b, double c, double hh) {
    x.push_back(a);
    y.push_back(b);
    z.push_back(c);
    h.push_back(hh);
  }
};

// Exact: j != i with |x_i - x_j| < h_i + h_j, compared with the same arithmetic as the search.
std::vector<std::uint32_t> brute_force(const Cloud& c, std::size_t i) {
  std::vector<std::uint32_t> out;
  for (std::size_t j = 0; j < c.size(); ++j) {
    if (j == i) continue;
    const double dx = c.x[i] - c.x[j], dy = c.y[i] - c.y[j], dz = c.z[i] - c.z[j];
    const double reach = c.h[i] + c.h[j];
    if (dx * dx + dy * dy + dz * dz < reach * reach) out.push_back(static_cast<std::uint32_t>(j));
  }
  return out;
}

void expect_matches_brute_force(const Cloud& c, const NeighbourSearch& s) {
  ASSERT_EQ(s.size(), c.size());
  std::size_t pairs = 0;
  for (std::size_t i = 0; i < c.size(); ++i) {
    const auto got_span = s.of(i);
    std::vector<std::uint32_t> got(got_span.begin(), got_span.end());
    std::sort(got.begin(), got.end());
    ASSERT_EQ(got, brute_force(c, i)) << "point " << i;
    pairs += got.size();
  }
  EXPECT_EQ(s.pairs(), pairs);
  EXPECT_GT(pairs, 0u);
}

TEST(NeighbourSearch, RandomPointsWithVaryingHMatchBruteForce) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0), hu(0.02, 0.09);  // h varies 4.5x
  Cloud c;
  for (int k = 0; k < 2000; ++k) c.add(u(rng), u(rng), u(rng), hu(rng));
  NeighbourSearch s;
  s.build(c.x.data(), c.y.data(), c.z.data(), c.h.data(), c.size());
  expect_matches_brute_force(c, s);
  EXPECT_GE(s.cell_size(), 2.0 * *std::max_element(c.h.begin(), c.h.end()));
  // The sort buffers in lent storage (NeighbourSearch::lend): the same lists and cells, the
  // buffers' 32 B per point fewer held, and the storage used; too little lent: its own buffers.
  std::vector<double> storage(NeighbourSearch::sort_doubles(c.size()), -1.0);
  NeighbourSearch lent, short_lent;
  lent.lend(storage);
  lent.build(c.x.data(), c.y.data(), c.z.data(), c.h.data(), c.size());
  expect_matches_brute_force(c, lent);
  EXPECT_TRUE(std::equal(lent.cells().begin(), lent.cells().end(), s.cells().begin()));
  EXPECT_EQ(lent.bytes() + sizeof(double) * storage.size(), s.bytes());
  EXPECT_NE(std::count(storage.begin(), storage.end(), -1.0), std::ptrdiff_t(storage.size()));
  short_lent.lend(std::span<double>(storage).first(storage.size() - 1));
  short_lent.build(c.x.data(), c.y.data(), c.z.data(), c.h.data(), c.size());
  expect_matches_brute_force(c, short_lent);
  EXPECT_EQ(short_lent.bytes(), s.bytes());
}

TEST(NeighbourSearch, ClusteredPointsFarApartMatchBruteForce) {
  // Two dense Gaussian clusters 1000 h apart plus isolated far flyers: a dense cell array over
  // the bounding box would need ~1e9 cells at 2 max h; the sparse cells hold only occupied ones.
  std::mt19937_64 rng(11);
  std::normal_distribution<double> g(0.0, 0.05);
  std::uniform_real_distribution<double> hu(0.005, 0.02);
  Cloud c;
  for (int k = 0; k < 1500; ++k) c.add(g(rng), g(rng), g(rng), hu(rng));
  for (int k = 0; k < 1500; ++k) c.add(20.0 + g(rng), g(rng), -5.0 + g(rng), hu(rng));
  for (int k = 0; k < 20; ++k) c.add(-30.0 + 3.0 * k, 10.0, 7.0, 0.02);
  // Coincident points are each other's neighbours (r = 0 < h_i + h_j).
  c.add(0.3, 0.3, 0.3, 0.01);
  c.add(0.3, 0.3, 0.3, 0.01);
  NeighbourSearch s;
  s.build(c.x.data(), c.y.data(), c.z.data(), c.h.data(), c.size());
  expect_matches_brute_force(c, s);
  EXPECT_EQ(s.cell_size(), 2.0 * *std::max_element(c.h.begin(), c.h.end()));  // not coarsened
  EXPECT_LT(s.cell_count(), c.size());
}

TEST(NeighbourSearch, AFewWidePointsAreFoundFromBothSides) {
  // Most points of h in [0.02, 0.025], 40 "wide" ones of h up to 6 times that (as the SPH
  // solver's fast particles with large Verlet skins): the cells are sized for the many (edge
  // below 2 max h + skin), the wide points search wider stencils and list themselves for the
  // others, among them points without a list of their own (the last 600, as mirror images).
  // Every list against brute force with the skin, on 1 and 2 threads.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0), hu(0.02, 0.025), wide(0.05, 0.15);
  Cloud c;
  for (int k = 0; k < 4000; ++k) c.add(u(rng), u(rng), u(rng), k % 100 == 7 ? wide(rng) : hu(rng));
  constexpr std::size_t kLists = 3400;
  constexpr double kSkin = 0.004;
  NeighbourSearch one, two;
  tbb::task_arena(1).execute(
      [&] { one.build(c.x.data(), c.y.data(), c.z.data(), c.h.data(), c.size(), kLists, kSkin); });
  tbb::task_arena(2).execute(
      [&] { two.build(c.x.data(), c.y.data(), c.z.data(), c.h.data(), c.size(), kLists, kSkin); });
  const double hmax = *std::max_element(c.h.begin(), c.h.end());
  EXPECT_LT(one.cell_size(), 0.5 * (2.0 * hmax + kSkin));  // the wide points did not size the cells
  std::size_t wide_pairs = 0;
  for (std::size_t i = 0; i < kLists; ++i) {
    std::vector<std::uint32_t> want;
    for (std::size_t j = 0; j < c.size(); ++j) {
      const double dx = c.x[i] - c.x[j], dy = c.y[i] - c.y[j], dz = c.z[i] - c.z[j];
      const double reach = c.h[i] + c.h[j] + kSkin;
      if (j != i && kernels::sph::distance2(dx, dy, dz) < reach * reach) {  // the search's test
        want.push_back(static_cast<std::uint32_t>(j));
        wide_pairs += c.h[i] <= 0.025 && c.h[j] > 0.025 ? 1 : 0;
      }
    }
    const auto a = one.of(i), b = two.of(i);
    ASSERT_TRUE(std::equal(a.begin(), a.end(), want.begin(), want.end())) << "point " << i;
    ASSERT_TRUE(std::equal(b.begin(), b.end(), want.begin(), want.end())) << "point " << i;
  }
  EXPECT_GT(wide_pairs, 100u);
}

TEST(NeighbourSearch, ListsAreIdenticalForOneAndTwoThreadsAndRebuildsReuseMemory) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0), hu(0.03, 0.06);
  Cloud c;
  for (int k = 0; k < 3000; ++k) c.add(u(rng), u(rng), u(rng), hu(rng));
  NeighbourSearch one, two;
  tbb::task_arena(1).execute(
      [&] { one.build(c.x.data(), c.y.data(), c.z.data(), c.h.data(), c.size()); });
  tbb::task_arena(2).execute(
      [&] { two.build(c.x.data(), c.y.data(), c.z.data(), c.h.data(), c.size()); });
  ASSERT_EQ(one.pairs(), two.pairs());
  for (std::size_t i = 0; i < c.size(); ++i) {
    const auto a = one.of(i), b = two.of(i);
    ASSERT_TRUE(std::equal(a.begin(), a.end(), b.begin(), b.end())) << "point " << i;
  }
  // A rebuild after small moves (a step) keeps the buffers: no growth in held bytes unless the
  // pair count grows past its maximum.
  const std::size_t bytes = one.bytes();
  for (auto& v : c.x) v += 1e-4;
  one.build(c.x.data(), c.y.data(), c.z.data(), c.h.data(), c.size());
  if (one.pairs() <= two.pairs()) {
    EXPECT_EQ(one.bytes(), bytes);
  }
}

TEST(NeighbourSearch, PermutedListsAreTheListsOfABuildInTheNewNumbering) {
  // Lists with a skin for the first 2500 of 3000 points (the rest, like the SPH images, are
  // only neighbours), a bin in between (which must keep them), then the points renumbered: the
  // permuted lists must equal, entry for entry and in order, those built afresh for the
  // renumbered points, on 1 and 2 threads.
  constexpr std::size_t kPoints = 3000, kLists = 2500;
  constexpr double kSkin = 0.01;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0), hu(0.03, 0.06);
  Cloud c;
  for (std::size_t k = 0; k < kPoints; ++k) c.add(u(rng), u(rng), u(rng), hu(rng));
  // from[k]: the old point that becomes point k (the listed points among themselves, the
  // others among themselves); to: its inverse.
  std::vector<std::uint32_t> from(kPoints), to(kPoints);
  std::iota(from.begin(), from.end(), 0U);
  std::shuffle(from.begin(), from.begin() + kLists, rng);
  std::shuffle(from.begin() + kLists, from.end(), rng);
  for (std::size_t k = 0; k < kPoints; ++k) to[from[k]] = static_cast<std::uint32_t>(k);
  Cloud p;
  for (std::size_t k = 0; k < kPoints; ++k) {
    p.add(c.x[from[k]], c.y[from[k]], c.z[from[k]], c.h[from[k]]);
  }
  NeighbourSearch fresh;
  fresh.build(p.x.data(), p.y.data(), p.z.data(), p.h.data(), kPoints, kLists, kSkin);
  for (const int threads : {1, 2}) {
    NeighbourSearch s;
    tbb::task_arena(threads).execute([&] {
      s.build(c.x.data(), c.y.data(), c.z.data(), c.h.data(), kPoints, kLists, kSkin);
      s.bin(p.x.data(), p.y.data(), p.z.data(), p.h.data(), kPoints);
      s.permute({from.data(), kLists}, to);
    });
    ASSERT_EQ(s.lists(), kLists);
    ASSERT_EQ(s.pairs(), fresh.pairs());
    std::size_t moved = 0;
    for (std::size_t i = 0; i < kLists; ++i) {
      const auto a = s.of(i), b = fresh.of(i);
      ASSERT_TRUE(std::equal(a.begin(), a.end(), b.begin(), b.end())) << "point " << i;
      ASSERT_EQ(s.offset(i), fresh.offset(i));
      moved += from[i] != i ? 1 : 0;
    }
    EXPECT_GT(moved, kLists / 2);
  }
  // Sorting only the first half of each list (sort_first): those entries ascending, and each list
  // holding the same entries as the fresh one.
  NeighbourSearch half;
  half.build(c.x.data(), c.y.data(), c.z.data(), c.h.data(), kPoints, kLists, kSkin);
  std::vector<std::uint32_t> first(kLists);
  for (std::size_t k = 0; k < kLists; ++k) {
    first[k] = static_cast<std::uint32_t>(half.count(from[k]) / 2);
  }
  half.permute({from.data(), kLists}, to, first);
  std::size_t unsorted = 0;
  for (std::size_t i = 0; i < kLists; ++i) {
    const auto a = half.of(i);
    ASSERT_TRUE(std::is_sorted(a.begin(), a.begin() + first[i])) << "point " << i;
    unsorted += std::is_sorted(a.begin(), a.end()) ? 0 : 1;
    std::vector<std::uint32_t> got(a.begin(), a.end());
    std::sort(got.begin(), got.end());
    const auto b = fresh.of(i);
    ASSERT_TRUE(std::equal(got.begin(), got.end(), b.begin(), b.end())) << "point " << i;
  }
  EXPECT_GT(unsorted, kLists / 2);  // the rest was left as it came
  // A renumbering of the wrong number of lists or points: refused.
  NeighbourSearch s;
  s.build(c.x.data(), c.y.data(), c.z.data(), c.h.data(), kPoints, kLists, kSkin);
  EXPECT_THROW(s.permute({from.data(), kLists - 1}, to), std::invalid_argument);
  EXPECT_THROW(s.permute({from.data(), kLists}, {to.data(), kPoints - 1}), std::invalid_argument);
}

}  // namespace
}  // namespace shatter::sph
