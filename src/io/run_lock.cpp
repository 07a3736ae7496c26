#include "shatter/io/run_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <string>

#include <fmt/format.h>

namespace shatter::io {
namespace {

std::string host_name() {
  std::array<char, 256> name{};
  if (::gethostname(name.data(), name.size() - 1) != 0) return "unknown";
  return name.data();
}

std::string contents(int fd) {
  std::string text;
  std::array<char, 256> buffer{};
  ::lseek(fd, 0, SEEK_SET);
  for (ssize_t n; (n = ::read(fd, buffer.data(), buffer.size())) > 0;)
    text.append(buffer.data(), n);
  while (!text.empty() && (text.back() == '\n' || text.back() == '\0')) text.pop_back();
  return text;
}

// The host a holder line "pid N host H" names (empty when it cannot be parsed).
std::string host_of(const std::string& holder) {
  const auto at = holder.find(" host ");
  return at == std::string::npos ? std::string{} : holder.substr(at + 6);
}

}  // namespace

std::filesystem::path RunLock::file_in(const std::filesystem::path& dir) {
  return dir / "shatter.lock";
}

RunLock::RunLock(const std::filesystem::path& dir, bool take_over, std::string* taken_over)
    : file_(file_in(dir)) {
  std::filesystem::create_directories(dir);
  // The holder removes the file before it releases the lock: a process that opened the old
  // file meanwhile holds a lock on a removed file, so the lock counts only if the path still
  // names the file locked.
  for (int attempt = 0; fd_ < 0; ++attempt) {
    const int fd = ::open(file_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) {
      throw RunLocked(
          fmt::format("cannot create the lock file {}: {}", file_.string(), std::strerror(errno)));
    }
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int err = errno;
      const std::string holder = contents(fd);
      ::close(fd);
      throw RunLocked(
          fmt::format("{} is in use by another shatter ({}; lock file {}){}", dir.string(),
                      holder.empty() ? "holder unknown" : holder, file_.string(),
                      err == EWOULDBLOCK ? std::string(": wait for it to end, or stop it")
                                         : fmt::format(": {}", std::strerror(err))));
    }
    struct stat by_fd {
    }, by_path{};
    if (::fstat(fd, &by_fd) == 0 && ::stat(file_.c_str(), &by_path) == 0 &&
        by_fd.st_ino == by_path.st_ino && by_fd.st_dev == by_path.st_dev) {
      fd_ = fd;
    } else {
      ::close(fd);
      if (attempt > 100) throw RunLocked(fmt::format("cannot lock {}", file_.string()));
    }
  }
  const std::string stale = contents(fd_);
  const std::string host = host_name();
  if (!stale.empty() && host_of(stale) != host && !take_over) {
    ::close(fd_);
    fd_ = -1;
    throw RunLocked(fmt::format(
        "{} holds a lock of {} (lock file {}), a run on another host this one cannot check; if "
        "that run has ended, pass --take-lock",
        dir.string(), stale, file_.string()));
  }
  if (taken_over != nullptr) *taken_over = stale;
  const std::string line = fmt::format("pid {} host {}\n", ::getpid(), host);
  if (::ftruncate(fd_, 0) != 0 || ::pwrite(fd_, line.data(), line.size(), 0) < 0) {
    ::close(fd_);
    fd_ = -1;
    throw RunLocked(
        fmt::format("cannot write the lock file {}: {}", file_.string(), std::strerror(errno)));
  }
}

RunLock::~RunLock() {
  if (fd_ < 0) return;
  ::unlink(file_.c_str());
  ::close(fd_);
}

}  // namespace shatter::io
