// The time series of a porous scene (issue 29): the mean_porosity column (before wall_s) only
// when the writer is made porous, its value the mass-weighted mean of 1 - 1/alpha over the porous
// points, and a resume that refuses a file of the other kind rather than mix the two layouts.

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <string>
#include <vector>

#include "sample_store.hpp"
#include "scratch_dir.hpp"
#include "shatter/io/timeseries.hpp"

namespace shatter::io {
namespace {

using test::sample_store;
using test::ScratchDir;

std::vector<std::string> lines(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::vector<std::string> out;
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

TEST(TimeSeriesPorosity, HeaderHasMeanPorosityBeforeWallOnlyWhenPorous) {
  const std::string dense = timeseries_header(false), porous = timeseries_header(true);
  EXPECT_EQ(dense.find("mean_porosity"), std::string::npos);
  EXPECT_EQ(porous, dense.substr(0, dense.size() - 6) + "mean_porosity,compaction_J,wall_s");
}

TEST(TimeSeriesPorosity, RowsCarryTheValueInItsColumn) {
  ScratchDir dir;
  {
    TimeSeriesWriter w(dir / "ts.csv", true);
    TimeSeriesRow r;
    r.step = 3;
    r.mean_porosity = 0.1875;
    r.compaction_work = 2.5;
    r.wall = 1.5;
    w.write(r);
  }
  const auto l = lines(dir / "ts.csv");
  ASSERT_EQ(l.size(), 2u);
  EXPECT_EQ(l[0], timeseries_header(true));
  EXPECT_NE(l[1].find(",0.1875,2.5,1.500"), std::string::npos) << l[1];
  EXPECT_EQ(std::count(l[1].begin(), l[1].end(), ','), std::count(l[0].begin(), l[0].end(), ','));
}

TEST(TimeSeriesPorosity, MeanIsMassWeightedOverThePorousPointsOnly) {
  ParticleStore s = sample_store(2, 2);
  s.require(Field::distension);
  // points 0, 1: porous (alpha 2 and 1.25: porosity 0.5 and 0.2); 2, 3: dense (column fill 0)
  const double m[] = {1.0, 3.0, 100.0, 100.0};
  const double a[] = {2.0, 1.25, 0.0, 0.0};
  for (std::size_t p = 0; p < 4; ++p) {
    s.col(Field::mass)[p] = m[p];
    s.col(Field::distension)[p] = a[p];
  }
  // (1 * 0.5 + 3 * 0.2) / (1 + 3) = 0.275, exact sums then one rounding
  EXPECT_NEAR(mean_porosity(s), 0.275, 1e-16);
  // a fully compacted point (alpha = 1) counts, with porosity 0
  s.col(Field::distension)[0] = 1.0;
  EXPECT_NEAR(mean_porosity(s), 0.15, 1e-16);
  // no distension column: 0
  EXPECT_EQ(mean_porosity(sample_store(2, 2)), 0.0);
}

TEST(TimeSeriesPorosity, CompactionWorkSumsMassTimesCompactionHeatOfThePorousPoints) {
  ParticleStore s = sample_store(2, 2);
  s.require(Field::distension);
  s.require(Field::compaction_heat);
  const double m[] = {1.0, 3.0, 100.0, 100.0};
  const double a[] = {2.0, 1.25, 0.0, 0.0};
  const double q[] = {1000.0, 250.0, 7.0, 7.0};  // the dense points' values are not summed
  for (std::size_t p = 0; p < 4; ++p) {
    s.col(Field::mass)[p] = m[p];
    s.col(Field::distension)[p] = a[p];
    s.col(Field::compaction_heat)[p] = q[p];
  }
  auto sums = porosity_sums(s);
  EXPECT_EQ(sums[2].value(), 1750.0);  // 1 * 1000 + 3 * 250, exact
}

TEST(TimeSeriesPorosity, ResumeRefusesAFileOfTheOtherLayout) {
  ScratchDir dir;
  {
    TimeSeriesWriter w(dir / "ts.csv", false);
    TimeSeriesRow r;
    w.write(r);
  }
  EXPECT_THROW(TimeSeriesWriter(dir / "ts.csv", ResumeRows{0}, true), std::runtime_error);
  EXPECT_NO_THROW(TimeSeriesWriter(dir / "ts.csv", ResumeRows{0}, false));
}

}  // namespace
}  // namespace shatter::io
