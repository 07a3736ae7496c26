// `shatter run` and `shatter resume` as a user runs them, on tests/fuzz/tiny.toml (a lab impact
// in miniature, ~0.5 s): the progress guard's exit code and post-mortem file, a resumed run that
// matches an uninterrupted one byte for byte, a corrupt checkpoint refused by name, the run's
// last outputs completed by a resume at the end time, and `run --check`.

#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "support/cli_run.hpp"

namespace shatter {
namespace {

namespace fs = std::filesystem;
using test::kTiny;
using test::slurp;

struct Result {
  int code = -1;
  std::string err;
};

class Reliability : public test::TempDirTest {
 protected:
  Reliability() : TempDirTest("cli") {}

  Result shatter(const std::vector<std::string>& args) const {
    std::string cmd = test::shatter_command(args);
    cmd += " --threads 1 2>'" + (dir_ / "stderr.txt").string() + "' >/dev/null";
    const int status = std::system(cmd.c_str());
    return {test::exit_code(status), slurp(dir_ / "stderr.txt")};
  }

  // Every file of a run directory, timeseries.csv without its wall-clock column.
  static std::map<std::string, std::string> outputs(const fs::path& out) {
    std::map<std::string, std::string> files;
    for (const auto& e : fs::recursive_directory_iterator(out)) {
      if (!e.is_regular_file()) continue;
      const std::string rel = fs::relative(e.path(), out).string();
      std::string data = slurp(e.path());
      if (rel == "timeseries.csv") {
        std::string stripped, line;
        std::istringstream in(data);
        while (std::getline(in, line)) stripped += line.substr(0, line.rfind(',')) + "\n";
        data = stripped;
      }
      files[rel] = data;
    }
    return files;
  }
};

TEST_F(Reliability, CollapsingTimeStepStopsWithExit3AndAPostMortem) {
  // The tiny run's smallest step is 0.32 of its first (measured); a floor of 0.9 must stop it.
  const fs::path out = dir_ / "run";
  const Result r =
      shatter({"run", kTiny.string(), "--out", out.string(), "--set", "solver.dt_floor_ratio=0.9"});
  EXPECT_EQ(r.code, 3) << r.err;
  EXPECT_NE(r.err.find("time step collapsed"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("particle"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("soundspeed"), std::string::npos) << r.err;
  bool post_mortem = false;
  for (const auto& e : fs::directory_iterator(out)) {
    post_mortem |= e.path().filename().string().rfind("failed_step", 0) == 0;
  }
  EXPECT_TRUE(post_mortem) << "no failed_step*.h5 in " << out;
}

TEST_F(Reliability, ResumedRunMatchesTheUninterruptedRunByteForByte) {
  // Run A to the end; run B to half the end time, then resume it to the end. Every output but
  // scene.toml (its header records the --set) must be identical, the rows after the resume
  // included (the internal energy at t^{n+1} comes from the checkpoint, not a new sum).
  // The target moves at 8 km/s towards an outflow face 2 mm away, so particles leave from step
  // 13 (t = 0.32 us) on, before the checkpoint at 0.5 us: the outflow stage books their internal
  // energy by subtraction, which a new sum over the remaining particles need not reproduce bit
  // for bit.
  const std::vector<std::string> outflow = {"--set", "domain.hi=[0.012,0.05,0.05]", "--set",
                                            "body.target.velocity=[8000.0,0.0,0.0]"};
  auto run = [&](const fs::path& out, std::vector<std::string> extra) {
    std::vector<std::string> args = {"run", kTiny.string(), "--out", out.string()};
    args.insert(args.end(), outflow.begin(), outflow.end());
    args.insert(args.end(), extra.begin(), extra.end());
    return shatter(args).code;
  };
  const fs::path a = dir_ / "a", b = dir_ / "b";
  ASSERT_EQ(run(a, {}), 0);
  ASSERT_EQ(run(b, {"--set", "solver.end_time=0.5e-6"}), 0);
  const Result r =
      shatter({"resume", (b / "checkpoint.h5").string(), "--set", "solver.end_time=1.0e-6"});
  ASSERT_EQ(r.code, 0) << r.err;
  auto fa = outputs(a), fb = outputs(b);
  fa.erase("scene.toml");
  fb.erase("scene.toml");
  fa.erase("checkpoint.h5");  // its scene text holds the end time it was started with
  fb.erase("checkpoint.h5");
  ASSERT_EQ(fa.size(), fb.size());
  for (const auto& [name, data] : fa) {
    EXPECT_TRUE(fb[name] == data) << name << " differs after the resume";
  }
}

TEST_F(Reliability, CorruptCheckpointIsRefusedNamingTheDataset) {
  const fs::path out = dir_ / "run";
  ASSERT_EQ(
      shatter({"run", kTiny.string(), "--out", out.string(), "--set", "solver.end_time=0.5e-6"})
          .code,
      0);
  const fs::path cp = out / "checkpoint.h5";
  haddr_t at = 0;
  {
    const hid_t f = H5Fopen(cp.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    const hid_t d = H5Dopen2(f, "/particles/vx", H5P_DEFAULT);
    at = H5Dget_offset(d);
    H5Dclose(d);
    H5Fclose(f);
  }
  {
    // 64 bytes flipped, as in the issue (it resumed silently and ran to the end).
    std::fstream f(cp, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(at) + 128);
    f.write(std::string(64, '\x5a').data(), 64);
  }
  const Result r = shatter({"resume", cp.string(), "--set", "solver.end_time=1.0e-6"});
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("'/particles/vx' is corrupt"), std::string::npos) << r.err;
}

TEST_F(Reliability, ResumeAtTheEndCompletesTheLastOutputs) {
  // A run killed after its last checkpoint but before the fragment catalogue: resuming writes
  // the catalogue (identical) and changes nothing else.
  const fs::path out = dir_ / "run";
  ASSERT_EQ(shatter({"run", kTiny.string(), "--out", out.string()}).code, 0);
  const auto before = outputs(out);
  fs::remove(out / "fragments.csv");
  fs::remove(out / "fragments.h5");
  const Result r = shatter({"resume", (out / "checkpoint.h5").string()});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("completing the run's last outputs"), std::string::npos) << r.err;
  const auto after = outputs(out);
  ASSERT_EQ(before.size(), after.size());
  for (const auto& [name, data] : before) EXPECT_TRUE(after.at(name) == data) << name;
}

TEST_F(Reliability, CheckValidatesAndWritesNothing) {
  const fs::path out = dir_ / "run";
  const Result ok = shatter({"run", kTiny.string(), "--out", out.string(), "--check"});
  EXPECT_EQ(ok.code, 0) << ok.err;
  EXPECT_FALSE(fs::exists(out));
  const Result bad = shatter(
      {"run", kTiny.string(), "--out", out.string(), "--check", "--set", "impact.speed=1e200"});
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("impact.speed"), std::string::npos) << bad.err;
}

TEST_F(Reliability, AbsurdThreadCountIsRefused) {
  // Was a segmentation fault inside oneTBB (found by tests/fuzz).
  std::string cmd = std::string("'") + SHATTER_BINARY + "' run '" + kTiny.string() +
                    "' --check --threads 999999999 2>/dev/null";
  const int status = std::system(cmd.c_str());
  EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 2);
}

}  // namespace
}  // namespace shatter
