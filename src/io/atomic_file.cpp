#include "shatter/io/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <fstream>
#include <stdexcept>

#include <fmt/format.h>

namespace shatter::io {
namespace {

void sync_path(const std::filesystem::path& path, int flags) {
  const int fd = ::open(path.c_str(), flags);
  if (fd < 0) return;  // nothing to flush (e.g. a directory we cannot open): rename still holds
  ::fsync(fd);
  ::close(fd);
}

}  // namespace

std::filesystem::path temporary_for(const std::filesystem::path& target) {
  std::filesystem::path tmp = target;
  tmp += ".tmp";
  return tmp;
}

void sync_file(const std::filesystem::path& file) {
  const int fd = ::open(file.c_str(), O_RDONLY);
  if (fd < 0) throw std::runtime_error(fmt::format("cannot open {} to sync it", file.string()));
  const int rc = ::fsync(fd);
  ::close(fd);
  if (rc != 0) throw std::runtime_error(fmt::format("cannot sync {} to disk", file.string()));
}

void commit(const std::filesystem::path& temporary, const std::filesystem::path& target) {
  sync_path(temporary, O_RDONLY);
  std::error_code ec;
  std::filesystem::rename(temporary, target, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);  // no temporary file left behind
    throw std::runtime_error(fmt::format("cannot rename {} to {}: {}", temporary.string(),
                                         target.string(), ec.message()));
  }
  const auto dir = target.has_parent_path() ? target.parent_path() : std::filesystem::path(".");
  sync_path(dir, O_RDONLY | O_DIRECTORY);
}

void write_text_atomically(const std::filesystem::path& target, std::string_view text) {
  const auto tmp = temporary_for(target);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(fmt::format("cannot write {}", tmp.string()));
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    out.flush();
    if (!out) throw std::runtime_error(fmt::format("error writing {}", tmp.string()));
  }
  commit(tmp, target);
}

}  // namespace shatter::io
