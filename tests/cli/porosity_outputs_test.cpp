// The outputs of a porous scene (issue 29) as a user gets them from `shatter run`: the default
// snapshot columns gain `distension`, `porosity` and `compaction_heat`, and the time series
// `mean_porosity` and `compaction_J`, when a body's material is porous, and neither appears for a
// dense scene; a resumed porous run continues the time series (its header has the extra column) row
// for row. On tests/fuzz/tiny.toml (~0.5 s a run), its target made porous basalt (eps-alpha, alpha0
// = 1.25: porosity 0.2) by --set.

#include <gtest/gtest.h>
#include <hdf5.h>

#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "support/cli_run.hpp"

namespace shatter {
namespace {

namespace fs = std::filesystem;
using test::kTiny;
using test::slurp;

class PorosityOutputs : public test::TempDirTest {
 protected:
  PorosityOutputs() : TempDirTest("porosity_outputs") {}

  int shatter(std::vector<std::string> args) const {
    std::string cmd = test::shatter_command(args);
    cmd += " --threads 1 2>'" + (dir_ / "stderr.txt").string() + "' >/dev/null";
    return test::exit_code(std::system(cmd.c_str()));
  }
  std::string err() const { return slurp(dir_ / "stderr.txt"); }

  // Runs the tiny scene to end_time, porous or not, into dir_/name.
  fs::path run(const std::string& name, bool porous, const std::string& end_time) const {
    const fs::path out = dir_ / name;
    std::vector<std::string> args = {"run",        kTiny.string(), "--out",
                                     out.string(), "--set",        "solver.end_time=" + end_time};
    if (porous) {
      args.insert(args.end(), {"--set", "body.target.material=\"porous_basalt\""});
    }
    EXPECT_EQ(shatter(args), 0) << err();
    return out;
  }

  // The rows of timeseries.csv split into cells (row 0: the header).
  static std::vector<std::vector<std::string>> rows(const fs::path& out) {
    std::vector<std::vector<std::string>> r;
    std::istringstream in(slurp(out / "timeseries.csv"));
    for (std::string line; std::getline(in, line);) {
      std::vector<std::string> cells;
      std::istringstream l(line);
      for (std::string c; std::getline(l, c, ',');) cells.push_back(c);
      r.push_back(cells);
    }
    return r;
  }

  static bool has_column(const fs::path& snapshot, const char* name) {
    const hid_t f = H5Fopen(snapshot.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    EXPECT_GE(f, 0) << snapshot;
    const bool found = H5Lexists(f, (std::string("/particles/") + name).c_str(), H5P_DEFAULT) > 0;
    H5Fclose(f);
    return found;
  }

  // A 1-column real dataset of a snapshot's particles.
  static std::vector<double> column(const fs::path& snapshot, const char* name) {
    const hid_t f = H5Fopen(snapshot.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    const hid_t d = H5Dopen2(f, (std::string("/particles/") + name).c_str(), H5P_DEFAULT);
    const hid_t sp = H5Dget_space(d);
    std::vector<double> v(static_cast<std::size_t>(H5Sget_simple_extent_npoints(sp)));
    EXPECT_GE(H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), 0) << name;
    H5Sclose(sp);
    H5Dclose(d);
    H5Fclose(f);
    return v;
  }

  static fs::path last_snapshot(const fs::path& out) {
    fs::path last;
    for (const auto& e : fs::directory_iterator(out / "snapshots")) {
      const auto n = e.path().filename().string();
      if (n.rfind("snapshot_", 0) == 0 && e.path().extension() == ".h5" &&
          (last.empty() || n > last.filename().string())) {
        last = e.path();
      }
    }
    EXPECT_FALSE(last.empty()) << "no snapshot in " << out;
    return last;
  }

  static fs::path first_snapshot(const fs::path& out) {
    for (const auto& e : fs::directory_iterator(out / "snapshots")) {
      if (e.path().filename().string().rfind("snapshot_", 0) == 0 &&
          e.path().extension() == ".h5") {
        return e.path();
      }
    }
    ADD_FAILURE() << "no snapshot in " << out;
    return {};
  }
};

TEST_F(PorosityOutputs, PorousSceneWritesDistensionAndMeanPorosity) {
  const fs::path out = run("porous", true, "0.5e-6");
  EXPECT_TRUE(has_column(first_snapshot(out), "distension"));
  const auto r = rows(out);
  ASSERT_GE(r.size(), 3u);
  const auto& h = r[0];
  ASSERT_GE(h.size(), 2u);
  EXPECT_EQ(h[h.size() - 3], "mean_porosity");
  EXPECT_EQ(h[h.size() - 2], "compaction_J");
  EXPECT_EQ(h.back(), "wall_s");
  for (const auto& row : r) ASSERT_EQ(row.size(), h.size());
  // Only the target is porous: its mean at t = 0 is 1 - 1/1.25 = 0.2 (rounding of the sums
  // only), and the impact compacts it (never below 0, never above 0.2: compaction is
  // irreversible and the eps-alpha curve starts at alpha0).
  const double phi0 = std::stod(r[1][h.size() - 3]);
  const double phi1 = std::stod(r.back()[h.size() - 3]);
  EXPECT_NEAR(phi0, 0.2, 1e-12);
  EXPECT_LT(phi1, phi0);
  EXPECT_GT(phi1, 0.0);

  // The snapshot columns porosity (1 - 1/alpha) and compaction_heat (J/kg) with the distension;
  // the time series' compaction_J is sum m q_c of the porous points: at t = 0 nothing, at the
  // end what the last snapshot (same time) holds, and part of internal_J.
  const fs::path last = last_snapshot(out);
  EXPECT_TRUE(has_column(last, "porosity"));
  EXPECT_TRUE(has_column(last, "compaction_heat"));
  const auto alpha = column(last, "distension"), phi = column(last, "porosity");
  const auto q = column(last, "compaction_heat"), m = column(last, "mass");
  ASSERT_EQ(alpha.size(), phi.size());
  double sum = 0.0;
  int compacted = 0;
  for (std::size_t i = 0; i < alpha.size(); ++i) {
    if (!(alpha[i] >= 1.0)) continue;  // the dense impactor
    EXPECT_NEAR(phi[i], 1.0 - 1.0 / alpha[i], 1e-15) << i;
    EXPECT_GE(q[i], 0.0) << i;  // eps-alpha with chi = 1: no reversible regime, work >= 0
    compacted += alpha[i] < 1.2;
    sum += m[i] * q[i];
  }
  EXPECT_GT(compacted, 0);
  EXPECT_EQ(std::stod(r[1][h.size() - 2]), 0.0);
  const double qj = std::stod(r.back()[h.size() - 2]);
  EXPECT_GT(qj, 0.0);
  EXPECT_NEAR(qj, sum, 1e-12 * qj);  // the same sum, summed in another order
  std::size_t internal = 0;
  while (h[internal] != "internal_J") ++internal;
  EXPECT_LT(qj, std::stod(r.back()[internal]));
}

TEST_F(PorosityOutputs, DenseSceneHasNeither) {
  const fs::path out = run("dense", false, "0.25e-6");
  EXPECT_FALSE(has_column(first_snapshot(out), "distension"));
  const auto r = rows(out);
  ASSERT_GE(r.size(), 2u);
  for (const auto& c : r[0]) EXPECT_NE(c, "mean_porosity");
  for (const auto& c : r[0]) EXPECT_NE(c, "compaction_J");
  EXPECT_FALSE(has_column(first_snapshot(out), "porosity"));
  EXPECT_EQ(r[0].back(), "wall_s");
}

TEST_F(PorosityOutputs, ResumedPorousRunContinuesTheTimeSeries) {
  // The resume reopens the file with the porous header (it would refuse a foreign one) and its
  // rows match the uninterrupted run's (wall clock aside).
  const fs::path a = run("a", true, "0.5e-6");
  const fs::path b = run("b", true, "0.25e-6");
  ASSERT_EQ(shatter({"resume", (b / "checkpoint.h5").string(), "--set", "solver.end_time=0.5e-6"}),
            0)
      << err();
  auto ra = rows(a), rb = rows(b);
  ASSERT_EQ(ra.size(), rb.size());
  for (std::size_t i = 0; i < ra.size(); ++i) {
    ASSERT_EQ(ra[i].size(), rb[i].size()) << "row " << i;
    // all but wall_s (the row 0 header included)
    for (std::size_t k = 0; k + 1 < ra[i].size(); ++k) {
      EXPECT_EQ(ra[i][k], rb[i][k]) << "row " << i << " column " << ra[0][k];
    }
  }
}

}  // namespace
}  // namespace shatter
