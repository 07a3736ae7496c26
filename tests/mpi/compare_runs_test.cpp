// compare_runs_test COMPARE_RUNS DIR: the column options of compare_runs. Two checkpoints of the
// same particles, one holding a column the other lacks (as a checkpoint written before the
// nine step-local deps_*/dspin_* columns left the store holds them): strict by default (a
// difference), equal with --common-columns or --ignore-column on that column, still a
// difference when a shared column differs, and a usage error for an unknown column name.
// Exit 0 when every case gives the expected exit status.

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <fmt/format.h>
#include <sys/wait.h>

#include "shatter/io/checkpoint.hpp"

namespace fs = std::filesystem;
using namespace shatter;

namespace {

ParticleStore store(bool with_deps, double x_shift) {
  ParticleStore s;
  s.require(FieldSet{Field::x, Field::vx, Field::rho});
  s.require(IField::id);
  if (with_deps) s.require(Field::deps_xx);
  s.add_group(0, 4);
  for (std::size_t p = 0; p < s.size(); ++p) {
    const double q = static_cast<double>(p);
    s.col(Field::x)[p] = std::sqrt(2.0) * q + x_shift;
    s.col(Field::vx)[p] = std::sin(q);
    s.col(Field::rho)[p] = 2700.0 + q / 3.0;
    s.col(IField::id)[p] = static_cast<std::int64_t>(10 + p);
    if (with_deps) s.col(Field::deps_xx)[p] = 1e-6 * q;
  }
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    fmt::print(stderr, "usage: compare_runs_test COMPARE_RUNS DIR\n");
    return 2;
  }
  const std::string tool = argv[1];
  const fs::path dir = argv[2];
  fs::create_directories(dir);
  const auto old_file = dir / "with_deps.h5", new_file = dir / "without_deps.h5",
             moved_file = dir / "moved.h5";
  io::RunState state;
  state.clock.time = 1e-6;
  state.clock.step = 7;
  io::write_checkpoint(old_file, store(true, 0.0), state);
  io::write_checkpoint(new_file, store(false, 0.0), state);
  io::write_checkpoint(moved_file, store(false, 1e-12), state);

  struct Case {
    std::string args;
    int expected;
  };
  const auto o = old_file.string(), n = new_file.string(), m = moved_file.string();
  const Case cases[] = {
      {fmt::format("{} {}", o, n), 1},                          // strict: one-file column
      {fmt::format("{} {} --common-columns", o, n), 0},         // compares x, vx, rho, id
      {fmt::format("{} {} --ignore-column deps_xx", o, n), 0},  // that column skipped
      {fmt::format("{} --ignore-column deps_xx {}", n, o), 0},  // either order
      {fmt::format("{} {} --ignore-column deps_yy", o, n), 1},  // another one skipped
      {fmt::format("{} {} --common-columns", o, m), 1},         // x differs
      {fmt::format("{} {} --ignore-column x --common-columns", o, m), 0},
      {fmt::format("{} {} --ignore-column no_such_column", o, n), 2},  // loud on a typo
      {fmt::format("{} {} --bogus", o, n), 2}};
  int failed = 0;
  for (const auto& c : cases) {
    const int status = std::system(fmt::format("{} {} > /dev/null 2>&1", tool, c.args).c_str());
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    if (code != c.expected) {
      fmt::print(stderr, "FAILED: compare_runs {} exited {}, expected {}\n", c.args, code,
                 c.expected);
      ++failed;
    }
  }
  fmt::print("{} of {} cases as expected\n", std::size(cases) - failed, std::size(cases));
  return failed == 0 ? 0 : 1;
}
