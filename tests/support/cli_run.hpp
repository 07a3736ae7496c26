#pragma once
// What the command-line tests (tests/cli) share: the tiny scene they run, reading a file whole,
// an exit status as the shell reports it, the command line of the built shatter, and a fixture
// that gives each test its own empty directory.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#ifndef SHATTER_BINARY
#error "SHATTER_BINARY must name the built shatter executable (tests/CMakeLists.txt)"
#endif

namespace shatter::test {

namespace fs = std::filesystem;

// A lab impact in miniature (~0.5 s).
inline const fs::path kTiny = fs::path(SHATTER_SOURCE_DIR) / "tests" / "fuzz" / "tiny.toml";

inline std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// The exit status of a std::system status; 128 + N when killed by signal N, -1 otherwise.
inline int exit_code(int status) {
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return -1;
}

// `'SHATTER_BINARY' 'ARG' ...`, each word quoted for the shell.
inline std::string shatter_command(const std::vector<std::string>& args) {
  std::string cmd = std::string("'") + SHATTER_BINARY + "'";
  for (const auto& a : args) cmd += " '" + a + "'";
  return cmd;
}

// A fresh directory per test, temp/shatter_<prefix>_<test>_<pid>, removed afterwards.
class TempDirTest : public ::testing::Test {
 protected:
  explicit TempDirTest(std::string prefix) : prefix_(std::move(prefix)) {}
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("shatter_" + prefix_ + "_" + std::string(info->name()) +
                                        "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  fs::path dir_;

 private:
  std::string prefix_;
};

}  // namespace shatter::test
