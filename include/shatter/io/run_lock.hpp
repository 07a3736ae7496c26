#pragma once
// An exclusive lock on a run directory (issue 33, item 4): two processes writing one run's files
// interleave its time series and overwrite each other's checkpoints. The lock is the file
// shatter.lock in the directory, held with flock(2) for the life of the run and naming its
// holder ("pid N host H"). The kernel releases an flock when its holder dies, so a lock file
// left by a killed run (kill -9, a crash) is found free: on the same host it is taken over and
// reported; one that names another host is taken over only with `take_over` (an flock may not
// reach across hosts on a network file system, so a live holder there cannot be ruled out).

#include <filesystem>
#include <stdexcept>
#include <string>

namespace shatter::io {

class RunLock {
 public:
  // Locks `dir` (created if missing). Throws RunLocked naming the holder when it is held, or
  // when a stale lock names another host and `take_over` is false. `taken_over`, when not null,
  // receives a description of the stale holder whose lock was taken over (empty if none).
  RunLock(const std::filesystem::path& dir, bool take_over, std::string* taken_over = nullptr);
  ~RunLock();  // removes the lock file, then releases the lock
  RunLock(const RunLock&) = delete;
  RunLock& operator=(const RunLock&) = delete;

  static std::filesystem::path file_in(const std::filesystem::path& dir);

 private:
  std::filesystem::path file_;
  int fd_ = -1;
};

struct RunLocked : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace shatter::io
