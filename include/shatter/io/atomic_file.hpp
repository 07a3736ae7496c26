#pragma once
// Crash-safe file replacement: write to a temporary file beside the target, flush it to disk,
// then rename it over the target. A crash at any point leaves either the old file or the new
// one, never a mixture (POSIX rename is atomic within one file system).

#include <filesystem>
#include <string_view>

namespace shatter::io {

// The temporary name used while `target` is being written.
std::filesystem::path temporary_for(const std::filesystem::path& target);

// Flushes `temporary` to disk and renames it to `target` (then flushes the directory entry).
void commit(const std::filesystem::path& temporary, const std::filesystem::path& target);

// fsync of a file's data (after its stream was flushed); throws when the file cannot be opened.
void sync_file(const std::filesystem::path& file);

// Writes `text` to `target` through a temporary file.
void write_text_atomically(const std::filesystem::path& target, std::string_view text);

// Call first in main, before any HDF5 call: HDF5 is not shut down at exit. After a write that
// failed for lack of space, H5Fclose fails and leaves the file half closed; HDF5's shutdown at
// exit then closed it again and crashed (a segmentation fault after the error message, issue
// 33). Every file shatter opens is closed by its owner, so there is nothing for it to do.
void skip_hdf5_shutdown_at_exit();

}  // namespace shatter::io
