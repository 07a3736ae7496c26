#include "shatter/io/timeseries.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <vector>

#include "sample_store.hpp"
#include "scratch_dir.hpp"

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

TimeSeriesRow row(std::uint64_t step, double t) {
  TimeSeriesRow r;
  r.step = step;
  r.time = t;
  r.dt = 1e-9;
  r.energy.kinetic = 2.0;
  r.energy.internal = 1.0;
  r.energy.initial = 3.0;
  r.energy.scale = 3.0;
  r.failure_ratio = 0.25;
  return r;
}

TEST(TimeSeries, HeaderNamesEveryQuantityWithItsUnit) {
  const std::string h(timeseries_header());
  for (const char* col : {"time_s", "dt_s", "kinetic_J", "internal_J", "total_J", "energy_error",
                          "px_kg_m_per_s", "py_kg_m_per_s", "pz_kg_m_per_s", "failure_ratio",
                          "unresolved_kinetic_J", "unresolved_kinetic_fraction"}) {
    EXPECT_NE(h.find(col), std::string::npos) << col;
  }
}

TEST(TimeSeries, OneRowPerSampleWithTotalAndError) {
  ScratchDir dir;
  {
    TimeSeriesWriter w(dir / "ts.csv");
    w.write(row(0, 0.0));
    TimeSeriesRow r = row(10, 1e-6);
    r.energy.kinetic = 2.5;  // total 3.5 against 3.0 initial, scale 3.0: error 1/6
    w.write(r);
  }
  const auto l = lines(dir / "ts.csv");
  ASSERT_EQ(l.size(), 3u);
  EXPECT_EQ(l[0], timeseries_header());
  EXPECT_EQ(l[2].substr(0, 3), "10,");
  EXPECT_NE(l[2].find(",3.5,"), std::string::npos) << l[2];
  EXPECT_NE(l[2].find(",0.166666667,"), std::string::npos) << l[2];
}

// The two columns before wall_s (which stays last: tests/mpi/compare_runs drops it): K_unresolved
// and its share of the transferred kinetic energy (issue 16); 0.5 of 2.0 J is 0.25 exactly.
TEST(TimeSeries, UnresolvedKineticAndItsFractionPrecedeTheWallTime) {
  ScratchDir dir;
  {
    TimeSeriesWriter w(dir / "ts.csv");
    TimeSeriesRow r = row(1, 1e-6);
    r.energy.transferred_kinetic = 2.0;
    r.energy.unresolved_kinetic = 0.5;
    w.write(r);
  }
  const auto l = lines(dir / "ts.csv");
  ASSERT_EQ(l.size(), 2u);
  EXPECT_NE(l[1].find(",0.5,0.25,"), std::string::npos) << l[1];
  EXPECT_EQ(l[0].substr(l[0].size() - 7), ",wall_s");
}

TEST(TimeSeries, ResumeDropsRowsWrittenAfterTheCheckpoint) {
  ScratchDir dir;
  {
    TimeSeriesWriter w(dir / "ts.csv");
    for (int k = 0; k < 5; ++k) w.write(row(static_cast<std::uint64_t>(k), 1e-6 * k));
  }
  std::ofstream(dir / "ts.csv", std::ios::app) << "5,0.0000";  // torn line from a crash
  {
    TimeSeriesWriter w(dir / "ts.csv", ResumeRows{2});
    w.write(row(3, 3e-6));
  }
  const auto l = lines(dir / "ts.csv");
  ASSERT_EQ(l.size(), 5u);  // header, steps 0 1 2, then the resumed step 3
  EXPECT_EQ(l[3].substr(0, 2), "2,");
  EXPECT_EQ(l[4].substr(0, 2), "3,");
}

TEST(TimeSeries, ResumeDropsRowsThatAreNotComplete) {
  // A crash can tear a row anywhere: within the time (which may then still parse, "0." for
  // "0.5"), or after all columns but before the newline. Neither may survive a resume.
  for (const std::string& torn :
       std::vector<std::string>{"3,0.", "3,3e-06,1e-06,1,2", std::string(64, 'x')}) {
    ScratchDir dir;
    {
      TimeSeriesWriter w(dir / "ts.csv");
      for (int k = 0; k < 3; ++k) w.write(row(static_cast<std::uint64_t>(k), 1e-6 * k));
    }
    std::ofstream(dir / "ts.csv", std::ios::app) << torn;
    { TimeSeriesWriter w(dir / "ts.csv", ResumeRows{2}); }
    const auto l = lines(dir / "ts.csv");
    ASSERT_EQ(l.size(), 4u) << torn;  // header and steps 0 1 2
    EXPECT_EQ(l[3].substr(0, 2), "2,");
  }
}

TEST(TimeSeries, ResumeKeepsTheRowAtTheCheckpointStepAndIsByteExact) {
  ScratchDir dir;
  {
    TimeSeriesWriter w(dir / "ts.csv");
    for (int k = 0; k < 4; ++k) w.write(row(static_cast<std::uint64_t>(k), 1e-6 * k / 3.0));
  }
  {
    TimeSeriesWriter w(dir / "ts.csv", ResumeRows{2});
    w.write(row(3, 1e-6));
    w.sync();
  }
  const auto l = lines(dir / "ts.csv");
  ASSERT_EQ(l.size(), 5u);
  EXPECT_EQ(l[3].substr(0, 2), "2,");
  EXPECT_EQ(l[4].substr(0, 2), "3,");
}

TEST(TimeSeries, ResumeRefusesAFileWithAnotherHeader) {
  // Rows of a file this program did not write are not silently thrown away.
  ScratchDir dir;
  std::ofstream(dir / "ts.csv") << "a,b,c\n1,2,3\n";
  EXPECT_THROW(TimeSeriesWriter(dir / "ts.csv", ResumeRows{1}), std::runtime_error);
  EXPECT_EQ(lines(dir / "ts.csv").size(), 2u);
}

void write_rows(const std::filesystem::path& file, int count) {
  TimeSeriesWriter w(file);
  for (int k = 0; k < count; ++k) w.write(row(static_cast<std::uint64_t>(k), 1e-6 * k));
}

TEST(TimeSeries, ResumeDropsTheRowAStopWroteAfterTheLastCoveredStep) {
  // Issue 33 item 5: a stop at step 7 with timeseries_every = 5 wrote rows 0, 5 and 7; the
  // checkpoint covers rows to step 5, so the row of step 7 goes (it was kept by its time).
  ScratchDir dir;
  {
    TimeSeriesWriter w(dir / "ts.csv");
    for (const std::uint64_t k : {0, 5, 7}) w.write(row(k, 1e-7 * static_cast<double>(k)));
  }
  { TimeSeriesWriter w(dir / "ts.csv", ResumeRows{5}); }
  const auto l = lines(dir / "ts.csv");
  ASSERT_EQ(l.size(), 3u);
  EXPECT_EQ(l[2].substr(0, 2), "5,");
}

TEST(TimeSeries, ResumeRefusesATimeSeriesShorterThanTheCheckpoint) {
  // Issue 33 item 6: deleted, emptied or truncated before a resume; was accepted silently.
  for (const std::string how : {"deleted", "emptied", "header only", "truncated"}) {
    ScratchDir dir;
    write_rows(dir / "ts.csv", 5);
    if (how == "deleted") std::filesystem::remove(dir / "ts.csv");
    if (how == "emptied") std::filesystem::resize_file(dir / "ts.csv", 0);
    if (how == "header only") {
      std::filesystem::resize_file(dir / "ts.csv", timeseries_header().size() + 1);
    }
    if (how == "truncated") {
      const auto l = lines(dir / "ts.csv");
      std::filesystem::resize_file(dir / "ts.csv",
                                   l[0].size() + l[1].size() + l[2].size() + 3);  // rows 0, 1
    }
    const auto before = std::filesystem::exists(dir / "ts.csv")
                            ? std::filesystem::file_size(dir / "ts.csv")
                            : std::uintmax_t{0};
    try {
      TimeSeriesWriter w(dir / "ts.csv", ResumeRows{4});
      ADD_FAILURE() << how << ": accepted";
    } catch (const TimeSeriesGap& e) {
      EXPECT_NE(std::string(e.what()).find("step 4"), std::string::npos) << e.what();
    }
    const auto after = std::filesystem::exists(dir / "ts.csv")
                           ? std::filesystem::file_size(dir / "ts.csv")
                           : std::uintmax_t{0};
    EXPECT_EQ(before, after) << how << ": a refused resume changed the file";
    // Accepted on request, saying so; the kept rows stay.
    TimeSeriesWriter w(dir / "ts.csv", ResumeRows{4, true});
    EXPECT_NE(w.note().find("missing"), std::string::npos) << how;
  }
}

TEST(TimeSeries, MomentumIsTheMassWeightedVelocitySum) {
  ParticleStore s = sample_store(2, 1);
  Eigen::Vector3d expected = Eigen::Vector3d::Zero();
  for (std::size_t p = 0; p < s.size(); ++p) {
    expected += s.col(Field::mass)[p] *
                Eigen::Vector3d(s.col(Field::vx)[p], s.col(Field::vy)[p], s.col(Field::vz)[p]);
  }
  EXPECT_EQ(total_momentum(s), expected);
}

TEST(TimeSeries, FailureRatioCountsOnlyFlaggedGroupsAtOrAboveThreshold) {
  ParticleStore s = sample_store(4, 4);
  const double d[] = {0.0, 0.9, 0.95, 0.89, 1.0, 1.0, 1.0, 1.0};
  for (std::size_t p = 0; p < 8; ++p) s.col(Field::damage)[p] = d[p];
  const std::vector<bool> first_only = {true, false};
  EXPECT_DOUBLE_EQ(failure_ratio(s, 0.9, first_only), 0.5);  // 0.9 counts as failed
  const std::vector<bool> both = {true, true};
  EXPECT_DOUBLE_EQ(failure_ratio(s, 0.9, both), 6.0 / 8.0);
  const std::vector<bool> none = {false, false};
  EXPECT_EQ(failure_ratio(s, 0.9, none), 0.0);
}

// The axisymmetric mode's failure ratio (a point is a ring whose mass grows with r): the failed
// points' share of the flagged groups' mass. Masses 1..8 kg, so the numbers are exact.
TEST(TimeSeries, FailedMassFractionWeighsThePointsByMass) {
  ParticleStore s = sample_store(4, 4);
  const double d[] = {0.0, 0.9, 0.95, 0.89, 1.0, 1.0, 1.0, 1.0};
  for (std::size_t p = 0; p < 8; ++p) {
    s.col(Field::damage)[p] = d[p];
    s.col(Field::mass)[p] = static_cast<double>(p + 1);
  }
  const std::vector<bool> first_only = {true, false};
  EXPECT_EQ(failed_mass_fraction(s, 0.9, first_only), (2.0 + 3.0) / (1.0 + 2.0 + 3.0 + 4.0));
  const std::vector<bool> both = {true, true};
  EXPECT_EQ(failed_mass_fraction(s, 0.9, both), (2.0 + 3.0 + 5.0 + 6.0 + 7.0 + 8.0) / 36.0);
  EXPECT_EQ(failed_mass_fraction(s, 0.9, {false, false}), 0.0);
  // The count-based ratio of the same points differs: the two measures are not the same thing.
  EXPECT_NE(failed_mass_fraction(s, 0.9, both), failure_ratio(s, 0.9, both));  // 31/36, 6/8
}

}  // namespace
}  // namespace shatter::io
