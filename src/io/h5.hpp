#pragma once
// Thin RAII and error-checking layer over the HDF5 1.10 C API, shared by the snapshot and
// checkpoint code. Every call that can fail is checked; a failure throws naming the file and the
// object, so a bad or truncated file is an error message, never a crash.

#include <hdf5.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace shatter::io::h5 {

// Owns one hid_t and closes it with the matching H5?close.
class Handle {
 public:
  using Closer = herr_t (*)(hid_t);
  Handle() = default;
  Handle(hid_t id, Closer close) : id_(id), close_(close) {}
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& o) noexcept : id_(o.id_), close_(o.close_) { o.id_ = -1; }
  Handle& operator=(Handle&& o) noexcept;
  ~Handle() { reset(); }
  void reset();
  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }

 private:
  hid_t id_ = -1;
  Closer close_ = nullptr;
};

// Silences HDF5's own error stack printing for the lifetime of the object; we report errors
// ourselves with the file and object named.
class QuietErrors {
 public:
  QuietErrors();
  ~QuietErrors();
  QuietErrors(const QuietErrors&) = delete;
  QuietErrors& operator=(const QuietErrors&) = delete;

 private:
  H5E_auto2_t func_ = nullptr;
  void* data_ = nullptr;
};

Handle create_file(const std::filesystem::path& path);  // truncates
// Writes `file` crash-safely: `write` fills a new file at its temporary name, which is then
// flushed and committed (shatter/io/atomic_file.hpp). A failure (a full disk) removes the
// temporary file and rethrows. The caller holds a QuietErrors.
void write_file_atomically(const std::filesystem::path& file,
                           const std::function<void(hid_t file)>& write);
Handle open_file(const std::filesystem::path& path);  // read-only
Handle create_group(hid_t parent, const std::string& name);
Handle open_group(hid_t parent, const std::string& name);
bool exists(hid_t parent, const std::string& name);
std::vector<std::string> children(hid_t group);

// Integrity: every dataset written here carries a "crc32" attribute, the CRC-32 (zlib) of its
// values as stored. A read recomputes it and throws naming the file and the dataset when it
// differs; a dataset without one is accepted (files from before checksums) unless `required`.
enum class Verify { if_present, required };
std::uint64_t checksum(const void* data, std::size_t bytes);

void write_doubles(hid_t parent, const std::string& name, std::span<const double> data);
void write_ints(hid_t parent, const std::string& name, std::span<const std::int64_t> data);
std::vector<double> read_doubles(hid_t parent, const std::string& name,
                                 Verify verify = Verify::if_present);
std::vector<std::int64_t> read_ints(hid_t parent, const std::string& name,
                                    Verify verify = Verify::if_present);
// How a real or integer dataset is stored. `compress`: chunked, byte-shuffled and deflated (the
// checksum covers the values, so it does not depend on the compression). `single`: reals as
// IEEE binary32 (the checksum then covers the binary32 values).
struct Storage {
  bool compress = false;
  bool single = false;
};
// Row-major rows x cols values; cols == 1 gives a 1-d dataset, otherwise a 2-d one.
void write_reals(hid_t parent, const std::string& name, std::span<const double> data,
                 std::size_t cols, Storage storage);
void write_ints(hid_t parent, const std::string& name, std::span<const std::int64_t> data,
                Storage storage);
// A 1-d or 2-d real dataset (binary64 or binary32) as doubles, with its shape.
struct RealTable {
  std::vector<double> values;
  std::size_t rows = 0;
  std::size_t cols = 1;
};
RealTable read_reals(hid_t parent, const std::string& name, Verify verify = Verify::if_present);
// Shape (1 or 2 dimensions) and bytes per value of a dataset.
struct DatasetShape {
  std::size_t rows = 0;
  std::size_t cols = 1;
  bool real = true;
  std::size_t bytes = 8;
};
DatasetShape dataset_shape(hid_t parent, const std::string& name);
// A 1-d dataset of fixed-length strings (null padded to the longest); checksum over the padded
// bytes as stored.
void write_strings(hid_t parent, const std::string& name, const std::vector<std::string>& values);
std::vector<std::string> read_strings(hid_t parent, const std::string& name,
                                      Verify verify = Verify::if_present);
// Kind of a dataset's values: true for floating point, false for integer.
bool is_float_dataset(hid_t parent, const std::string& name);
std::size_t dataset_size(hid_t parent, const std::string& name);

void set_attr(hid_t obj, const std::string& name, double value);
void set_attr(hid_t obj, const std::string& name, std::uint64_t value);
void set_attr(hid_t obj, const std::string& name, std::string_view value);
double get_attr_double(hid_t obj, const std::string& name);
std::uint64_t get_attr_u64(hid_t obj, const std::string& name);
std::string get_attr_string(hid_t obj, const std::string& name);
bool has_attr(hid_t obj, const std::string& name);

// Integrity of attributes (the header of a file): seal_attrs stores, on `obj`, the attribute
// "attributes_covered" (the names, space separated) and "attributes_crc32", the CRC-32 (zlib) of
// each covered attribute in turn (the covered list first) as: its name, a NUL, its value's byte
// length as a little-endian uint64, its value (numbers as native values, strings without their
// NUL padding). python/shatterpy computes the same bytes.
void seal_attrs(hid_t obj, const std::vector<std::string>& names);
// Verifies the seal: false when `obj` has none (older files); throws naming the file when the
// checksum differs, when a covered attribute is missing, or when one of `required` is not covered.
bool verify_attrs(hid_t obj, const std::vector<std::string>& required);

// Text stored as a scalar fixed-length string dataset (no 64 KiB attribute limit).
void write_text(hid_t parent, const std::string& name, std::string_view text);
std::string read_text(hid_t parent, const std::string& name, Verify verify = Verify::if_present);

// Name of the file an object lives in (for messages).
std::string file_name(hid_t obj);

}  // namespace shatter::io::h5
