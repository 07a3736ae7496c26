#include "io/h5.hpp"

#include <zlib.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <tuple>
#include <utility>

#include <fmt/format.h>

#include "shatter/io/atomic_file.hpp"

namespace shatter::io::h5 {
namespace {

[[noreturn]] void fail(hid_t where, std::string_view what, std::string_view name) {
  throw std::runtime_error(fmt::format("HDF5: cannot {} '{}' in {}", what, name, file_name(where)));
}

hid_t check(hid_t id, hid_t where, std::string_view what, std::string_view name) {
  if (id < 0) fail(where, what, name);
  return id;
}

void check(herr_t status, hid_t where, std::string_view what, std::string_view name) {
  if (status < 0) fail(where, what, name);
}

Handle open_dataset(hid_t parent, const std::string& name) {
  return {check(H5Dopen2(parent, name.c_str(), H5P_DEFAULT), parent, "open dataset", name),
          H5Dclose};
}

// Creation properties without modification times: HDF5 stamps every object header with the wall
// clock by default, so two runs that computed the same numbers would write different bytes.
// Without them a resumed run's files are byte-identical to an uninterrupted run's.
Handle untimed(hid_t cls) {
  Handle p{H5Pcreate(cls), H5Pclose};
  if (!p.valid() || H5Pset_obj_track_times(p.get(), 0) < 0) {
    throw std::runtime_error("HDF5: cannot make a creation property list");
  }
  return p;
}

// The checksum attribute of a dataset: CRC-32 (zlib, ISO 3309) of the values as stored in
// memory (native little-endian IEEE doubles / int64, or the text bytes).
constexpr const char* kChecksumAttr = "crc32";

void set_checksum(hid_t set, hid_t where, const std::string& name, const void* data,
                  std::size_t bytes) {
  const std::uint64_t crc = checksum(data, bytes);
  Handle space{check(H5Screate(H5S_SCALAR), where, "create dataspace for checksum of", name),
               H5Sclose};
  Handle a{check(H5Acreate2(set, kChecksumAttr, H5T_NATIVE_UINT64, space.get(), H5P_DEFAULT,
                            H5P_DEFAULT),
                 where, "create checksum of", name),
           H5Aclose};
  check(H5Awrite(a.get(), H5T_NATIVE_UINT64, &crc), where, "write checksum of", name);
}

// Full path of an object ("/particles/x"), for messages.
std::string object_path(hid_t obj, const std::string& fallback) {
  const ssize_t len = H5Iget_name(obj, nullptr, 0);
  if (len <= 0) return fallback;
  std::string path(static_cast<std::size_t>(len), '\0');
  H5Iget_name(obj, path.data(), path.size() + 1);
  return path;
}

void verify_checksum(hid_t set, hid_t where, const std::string& short_name, const void* data,
                     std::size_t bytes, Verify verify) {
  const std::string name = object_path(set, short_name);
  if (H5Aexists(set, kChecksumAttr) <= 0) {
    if (verify == Verify::required) {
      throw std::runtime_error(
          fmt::format("{}: dataset '{}' has no checksum (corrupt file?)", file_name(where), name));
    }
    return;
  }
  Handle a{check(H5Aopen(set, kChecksumAttr, H5P_DEFAULT), where, "open checksum of", name),
           H5Aclose};
  std::uint64_t stored = 0;
  check(H5Aread(a.get(), H5T_NATIVE_UINT64, &stored), where, "read checksum of", name);
  const std::uint64_t actual = checksum(data, bytes);
  if (stored != actual) {
    throw std::runtime_error(
        fmt::format("{}: dataset '{}' is corrupt: checksum {:08x}, stored {:08x}", file_name(where),
                    name, actual, stored));
  }
}

// Rows per chunk of a compressed dataset: 16384 rows of a 6-column binary64 table are 768 KiB,
// within HDF5's default 1 MiB chunk cache.
constexpr hsize_t kChunkRows = 16384;
constexpr unsigned kDeflateLevel = 4;  // zlib level: most of level 9's ratio at a third the time

Handle dataset_creation(int rank, const hsize_t* dims, hid_t where, const std::string& name,
                        bool compress) {
  Handle dcpl = untimed(H5P_DATASET_CREATE);
  if (compress && dims[0] > 0) {
    if (H5Zfilter_avail(H5Z_FILTER_DEFLATE) <= 0) fail(where, "deflate (no zlib filter)", name);
    const hsize_t chunk[2] = {std::min(dims[0], kChunkRows), rank == 2 ? dims[1] : 1};
    check(H5Pset_chunk(dcpl.get(), rank, chunk), where, "chunk", name);
    check(H5Pset_shuffle(dcpl.get()), where, "shuffle", name);
    check(H5Pset_deflate(dcpl.get(), kDeflateLevel), where, "deflate", name);
  }
  return dcpl;
}

template <class T>
void write_nd(hid_t parent, const std::string& name, hid_t type, const T* data, std::size_t rows,
              std::size_t cols, bool compress, std::size_t value_bytes = sizeof(T)) {
  const hsize_t dims[2] = {rows, cols};
  const int rank = cols == 1 ? 1 : 2;
  Handle space{check(H5Screate_simple(rank, dims, nullptr), parent, "create dataspace for", name),
               H5Sclose};
  Handle dcpl = dataset_creation(rank, dims, parent, name, compress);
  Handle set{check(H5Dcreate2(parent, name.c_str(), type, space.get(), H5P_DEFAULT, dcpl.get(),
                              H5P_DEFAULT),
                   parent, "create dataset", name),
             H5Dclose};
  // An empty dataset has no data to write (and HDF5 rejects a null buffer).
  if (rows * cols > 0) {
    check(H5Dwrite(set.get(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), parent, "write", name);
  }
  set_checksum(set.get(), parent, name, data, rows * cols * value_bytes);
}

template <class T>
void write_1d(hid_t parent, const std::string& name, hid_t type, std::span<const T> data) {
  write_nd(parent, name, type, data.data(), data.size(), 1, false);
}

template <class T>
std::vector<T> read_1d(hid_t parent, const std::string& name, hid_t type, Verify verify) {
  Handle set = open_dataset(parent, name);
  Handle space{check(H5Dget_space(set.get()), parent, "get dataspace of", name), H5Sclose};
  if (H5Sget_simple_extent_ndims(space.get()) != 1) fail(parent, "read 1-d dataset", name);
  hsize_t n = 0;
  H5Sget_simple_extent_dims(space.get(), &n, nullptr);
  std::vector<T> out(n);
  if (n > 0) {
    check(H5Dread(set.get(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()), parent, "read",
          name);
  }
  verify_checksum(set.get(), parent, name, out.data(), out.size() * sizeof(T), verify);
  return out;
}

Handle create_attr(hid_t obj, const std::string& name, hid_t type) {
  Handle space{check(H5Screate(H5S_SCALAR), obj, "create dataspace for attribute", name), H5Sclose};
  return {check(H5Acreate2(obj, name.c_str(), type, space.get(), H5P_DEFAULT, H5P_DEFAULT), obj,
                "create attribute", name),
          H5Aclose};
}

Handle open_attr(hid_t obj, const std::string& name) {
  return {check(H5Aopen(obj, name.c_str(), H5P_DEFAULT), obj, "open attribute", name), H5Aclose};
}

// Rows and columns of a 1-d or 2-d dataset.
std::pair<std::size_t, std::size_t> shape_of(hid_t set, hid_t parent, const std::string& name) {
  Handle space{check(H5Dget_space(set), parent, "get dataspace of", name), H5Sclose};
  const int rank = H5Sget_simple_extent_ndims(space.get());
  if (rank != 1 && rank != 2) fail(parent, "read 1-d or 2-d dataset", name);
  hsize_t dims[2] = {0, 1};
  H5Sget_simple_extent_dims(space.get(), dims, nullptr);
  return {static_cast<std::size_t>(dims[0]), static_cast<std::size_t>(rank == 2 ? dims[1] : 1)};
}

}  // namespace

void write_reals(hid_t parent, const std::string& name, std::span<const double> data,
                 std::size_t cols, Storage storage) {
  if (cols == 0 || data.size() % cols != 0) fail(parent, "shape table", name);
  const std::size_t rows = data.size() / cols;
  if (storage.single) {
    const std::vector<float> narrow(data.begin(), data.end());
    write_nd(parent, name, H5T_NATIVE_FLOAT, narrow.data(), rows, cols, storage.compress);
  } else {
    write_nd(parent, name, H5T_NATIVE_DOUBLE, data.data(), rows, cols, storage.compress);
  }
}

void write_ints(hid_t parent, const std::string& name, std::span<const std::int64_t> data,
                Storage storage) {
  write_nd(parent, name, H5T_NATIVE_INT64, data.data(), data.size(), 1, storage.compress);
}

RealTable read_reals(hid_t parent, const std::string& name, Verify verify) {
  Handle set = open_dataset(parent, name);
  Handle type{check(H5Dget_type(set.get()), parent, "get type of", name), H5Tclose};
  if (H5Tget_class(type.get()) != H5T_FLOAT) fail(parent, "read real dataset", name);
  RealTable t;
  std::tie(t.rows, t.cols) = shape_of(set.get(), parent, name);
  const std::size_t n = t.rows * t.cols;
  if (H5Tget_size(type.get()) == sizeof(float)) {
    std::vector<float> narrow(n);
    if (n > 0) {
      check(H5Dread(set.get(), H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, narrow.data()),
            parent, "read", name);
    }
    verify_checksum(set.get(), parent, name, narrow.data(), n * sizeof(float), verify);
    t.values.assign(narrow.begin(), narrow.end());
  } else {
    t.values.resize(n);
    if (n > 0) {
      check(H5Dread(set.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, t.values.data()),
            parent, "read", name);
    }
    verify_checksum(set.get(), parent, name, t.values.data(), n * sizeof(double), verify);
  }
  return t;
}

DatasetShape dataset_shape(hid_t parent, const std::string& name) {
  Handle set = open_dataset(parent, name);
  Handle type{check(H5Dget_type(set.get()), parent, "get type of", name), H5Tclose};
  DatasetShape d;
  std::tie(d.rows, d.cols) = shape_of(set.get(), parent, name);
  d.real = H5Tget_class(type.get()) == H5T_FLOAT;
  d.bytes = H5Tget_size(type.get());
  return d;
}

void write_strings(hid_t parent, const std::string& name, const std::vector<std::string>& values) {
  std::size_t width = 1;
  for (const auto& v : values) width = std::max(width, v.size());
  std::string buffer(width * values.size(), '\0');
  for (std::size_t i = 0; i < values.size(); ++i) {
    std::copy(values[i].begin(), values[i].end(), buffer.begin() + static_cast<long>(i * width));
  }
  Handle type{check(H5Tcopy(H5T_C_S1), parent, "copy string type for", name), H5Tclose};
  check(H5Tset_size(type.get(), width), parent, "size", name);
  check(H5Tset_strpad(type.get(), H5T_STR_NULLPAD), parent, "pad string", name);
  write_nd(parent, name, type.get(), buffer.data(), values.size(), 1, false, width);
}

std::vector<std::string> read_strings(hid_t parent, const std::string& name, Verify verify) {
  Handle set = open_dataset(parent, name);
  Handle type{check(H5Dget_type(set.get()), parent, "get type of", name), H5Tclose};
  if (H5Tget_class(type.get()) != H5T_STRING || H5Tis_variable_str(type.get()) > 0) {
    fail(parent, "read fixed-length string dataset", name);
  }
  const std::size_t width = H5Tget_size(type.get());
  const auto [rows, cols] = shape_of(set.get(), parent, name);
  if (cols != 1) fail(parent, "read 1-d string dataset", name);
  std::string buffer(rows * width, '\0');
  if (rows > 0) {
    check(H5Dread(set.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer.data()), parent,
          "read", name);
  }
  verify_checksum(set.get(), parent, name, buffer.data(), buffer.size(), verify);
  std::vector<std::string> out;
  for (std::size_t i = 0; i < rows; ++i) {
    std::string v = buffer.substr(i * width, width);
    while (!v.empty() && v.back() == '\0') v.pop_back();
    out.push_back(std::move(v));
  }
  return out;
}

std::uint64_t checksum(const void* data, std::size_t bytes) {
  // zlib's length argument is 32-bit: feed large buffers in pieces.
  uLong crc = crc32(0L, Z_NULL, 0);
  const auto* p = static_cast<const Bytef*>(data);
  while (bytes > 0) {
    const auto n = static_cast<uInt>(std::min<std::size_t>(bytes, 1u << 30));
    crc = crc32(crc, p, n);
    p += n;
    bytes -= n;
  }
  return static_cast<std::uint64_t>(crc);
}

Handle& Handle::operator=(Handle&& o) noexcept {
  if (this != &o) {
    reset();
    id_ = o.id_;
    close_ = o.close_;
    o.id_ = -1;
  }
  return *this;
}

void Handle::reset() {
  if (id_ >= 0 && close_ != nullptr) close_(id_);
  id_ = -1;
}

QuietErrors::QuietErrors() {
  H5Eget_auto2(H5E_DEFAULT, &func_, &data_);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

QuietErrors::~QuietErrors() {
  H5Eset_auto2(H5E_DEFAULT, func_, data_);
}

Handle create_file(const std::filesystem::path& path) {
  const hid_t id = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (id < 0) throw std::runtime_error(fmt::format("HDF5: cannot create file {}", path.string()));
  return {id, H5Fclose};
}

void write_file_atomically(const std::filesystem::path& file,
                           const std::function<void(hid_t file)>& write) {
  const auto tmp = temporary_for(file);
  try {
    Handle f = create_file(tmp);
    write(f.get());
    if (H5Fflush(f.get(), H5F_SCOPE_GLOBAL) < 0) {
      throw std::runtime_error(fmt::format("cannot flush {}", tmp.string()));
    }
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw;
  }
  commit(tmp, file);
}

Handle open_file(const std::filesystem::path& path) {
  if (!std::filesystem::exists(path)) {
    throw std::runtime_error(fmt::format("no such file: {}", path.string()));
  }
  const hid_t id = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (id < 0) {
    throw std::runtime_error(
        fmt::format("{} is not a readable HDF5 file (truncated or corrupt?)", path.string()));
  }
  return {id, H5Fclose};
}

Handle create_group(hid_t parent, const std::string& name) {
  Handle gcpl = untimed(H5P_GROUP_CREATE);
  return {check(H5Gcreate2(parent, name.c_str(), H5P_DEFAULT, gcpl.get(), H5P_DEFAULT), parent,
                "create group", name),
          H5Gclose};
}

Handle open_group(hid_t parent, const std::string& name) {
  if (!exists(parent, name)) fail(parent, "find group", name);
  return {check(H5Gopen2(parent, name.c_str(), H5P_DEFAULT), parent, "open group", name), H5Gclose};
}

bool exists(hid_t parent, const std::string& name) {
  return H5Lexists(parent, name.c_str(), H5P_DEFAULT) > 0;
}

std::vector<std::string> children(hid_t group) {
  H5G_info_t info;
  check(H5Gget_info(group, &info), group, "list group", "");
  std::vector<std::string> names;
  for (hsize_t i = 0; i < info.nlinks; ++i) {
    const ssize_t len =
        H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0, H5P_DEFAULT);
    if (len < 0) fail(group, "list group", "");
    std::string name(static_cast<std::size_t>(len), '\0');
    H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, i, name.data(), name.size() + 1,
                       H5P_DEFAULT);
    names.push_back(std::move(name));
  }
  return names;
}

void write_doubles(hid_t parent, const std::string& name, std::span<const double> data) {
  write_1d(parent, name, H5T_NATIVE_DOUBLE, data);
}

void write_ints(hid_t parent, const std::string& name, std::span<const std::int64_t> data) {
  write_1d(parent, name, H5T_NATIVE_INT64, data);
}

std::vector<double> read_doubles(hid_t parent, const std::string& name, Verify verify) {
  return read_1d<double>(parent, name, H5T_NATIVE_DOUBLE, verify);
}

std::vector<std::int64_t> read_ints(hid_t parent, const std::string& name, Verify verify) {
  return read_1d<std::int64_t>(parent, name, H5T_NATIVE_INT64, verify);
}

bool is_float_dataset(hid_t parent, const std::string& name) {
  Handle set = open_dataset(parent, name);
  Handle type{check(H5Dget_type(set.get()), parent, "get type of", name), H5Tclose};
  return H5Tget_class(type.get()) == H5T_FLOAT;
}

std::size_t dataset_size(hid_t parent, const std::string& name) {
  Handle set = open_dataset(parent, name);
  Handle space{check(H5Dget_space(set.get()), parent, "get dataspace of", name), H5Sclose};
  const hssize_t n = H5Sget_simple_extent_npoints(space.get());
  if (n < 0) fail(parent, "size", name);
  return static_cast<std::size_t>(n);
}

void set_attr(hid_t obj, const std::string& name, double value) {
  Handle a = create_attr(obj, name, H5T_NATIVE_DOUBLE);
  check(H5Awrite(a.get(), H5T_NATIVE_DOUBLE, &value), obj, "write attribute", name);
}

void set_attr(hid_t obj, const std::string& name, std::uint64_t value) {
  Handle a = create_attr(obj, name, H5T_NATIVE_UINT64);
  check(H5Awrite(a.get(), H5T_NATIVE_UINT64, &value), obj, "write attribute", name);
}

void set_attr(hid_t obj, const std::string& name, std::string_view value) {
  // Fixed-length string of the exact size: h5dump, h5py and ParaView all read it as text.
  Handle type{check(H5Tcopy(H5T_C_S1), obj, "copy string type for", name), H5Tclose};
  check(H5Tset_size(type.get(), std::max<std::size_t>(value.size(), 1)), obj, "size string", name);
  check(H5Tset_strpad(type.get(), H5T_STR_NULLPAD), obj, "pad string", name);
  Handle a = create_attr(obj, name, type.get());
  std::string buffer(value);
  if (buffer.empty()) buffer.push_back('\0');
  check(H5Awrite(a.get(), type.get(), buffer.data()), obj, "write attribute", name);
}

double get_attr_double(hid_t obj, const std::string& name) {
  Handle a = open_attr(obj, name);
  double v = 0.0;
  check(H5Aread(a.get(), H5T_NATIVE_DOUBLE, &v), obj, "read attribute", name);
  return v;
}

std::uint64_t get_attr_u64(hid_t obj, const std::string& name) {
  Handle a = open_attr(obj, name);
  std::uint64_t v = 0;
  check(H5Aread(a.get(), H5T_NATIVE_UINT64, &v), obj, "read attribute", name);
  return v;
}

std::string get_attr_string(hid_t obj, const std::string& name) {
  Handle a = open_attr(obj, name);
  Handle type{check(H5Aget_type(a.get()), obj, "get type of attribute", name), H5Tclose};
  if (H5Tget_class(type.get()) != H5T_STRING || H5Tis_variable_str(type.get()) > 0) {
    fail(obj, "read fixed-length string attribute", name);
  }
  std::string out(H5Tget_size(type.get()), '\0');
  check(H5Aread(a.get(), type.get(), out.data()), obj, "read attribute", name);
  while (!out.empty() && out.back() == '\0') out.pop_back();
  return out;
}

bool has_attr(hid_t obj, const std::string& name) {
  return H5Aexists(obj, name.c_str()) > 0;
}

namespace {

constexpr const char* kCoveredAttr = "attributes_covered";
constexpr const char* kSealAttr = "attributes_crc32";

// An attribute's value as the seal covers it: numbers as native values, strings without their
// NUL padding (as h5py returns them).
std::string attr_bytes(hid_t obj, const std::string& name) {
  Handle a = open_attr(obj, name);
  Handle type{check(H5Aget_type(a.get()), obj, "get type of attribute", name), H5Tclose};
  Handle space{check(H5Aget_space(a.get()), obj, "get dataspace of attribute", name), H5Sclose};
  const hssize_t n = H5Sget_simple_extent_npoints(space.get());
  if (n < 0) fail(obj, "size attribute", name);
  const auto count = static_cast<std::size_t>(n);
  if (H5Tget_class(type.get()) == H5T_STRING) {
    if (H5Tis_variable_str(type.get()) > 0) fail(obj, "read fixed-length attribute", name);
    std::string out(H5Tget_size(type.get()) * count, '\0');
    check(H5Aread(a.get(), type.get(), out.data()), obj, "read attribute", name);
    while (!out.empty() && out.back() == '\0') out.pop_back();
    return out;
  }
  Handle native{check(H5Tget_native_type(type.get(), H5T_DIR_ASCEND), obj, "type attribute", name),
                H5Tclose};
  std::string out(H5Tget_size(native.get()) * count, '\0');
  check(H5Aread(a.get(), native.get(), out.data()), obj, "read attribute", name);
  return out;
}

std::uint64_t seal_of(hid_t obj, const std::vector<std::string>& names) {
  std::string bytes;
  for (const std::string& name : names) {
    const std::string value = attr_bytes(obj, name);
    const std::uint64_t size = value.size();  // little-endian on every platform we build for
    bytes += name;
    bytes.push_back('\0');
    bytes.append(reinterpret_cast<const char*>(&size), sizeof(size));
    bytes += value;
  }
  return checksum(bytes.data(), bytes.size());
}

}  // namespace

void seal_attrs(hid_t obj, const std::vector<std::string>& names) {
  std::string covered;
  for (const std::string& name : names) covered += (covered.empty() ? "" : " ") + name;
  set_attr(obj, kCoveredAttr, std::string_view(covered));
  std::vector<std::string> all{kCoveredAttr};
  all.insert(all.end(), names.begin(), names.end());
  set_attr(obj, kSealAttr, seal_of(obj, all));
}

bool verify_attrs(hid_t obj, const std::vector<std::string>& required) {
  const std::string where = object_path(obj, "/");
  const bool has_seal = has_attr(obj, kSealAttr), has_list = has_attr(obj, kCoveredAttr);
  if (!has_seal && !has_list) return false;
  if (!has_seal || !has_list) {
    throw std::runtime_error(
        fmt::format("{}: the attributes of '{}' have a broken checksum "
                    "(attribute {} missing): corrupt file",
                    file_name(obj), where, has_seal ? kCoveredAttr : kSealAttr));
  }
  std::vector<std::string> all{kCoveredAttr};
  const std::string covered = get_attr_string(obj, kCoveredAttr);
  for (std::size_t pos = 0; pos < covered.size();) {
    const auto space = std::min(covered.find(' ', pos), covered.size());
    if (space > pos) all.push_back(covered.substr(pos, space - pos));
    pos = space + 1;
  }
  for (const std::string& name : required) {
    if (std::find(all.begin(), all.end(), name) == all.end()) {
      throw std::runtime_error(fmt::format(
          "{}: attribute '{}' of '{}' is not covered by the attribute checksum: corrupt file",
          file_name(obj), name, where));
    }
  }
  for (const std::string& name : all) {
    if (!has_attr(obj, name)) {
      throw std::runtime_error(fmt::format("{}: attribute '{}' of '{}' is missing: corrupt file",
                                           file_name(obj), name, where));
    }
  }
  const std::uint64_t stored = get_attr_u64(obj, kSealAttr), actual = seal_of(obj, all);
  if (stored != actual) {
    throw std::runtime_error(
        fmt::format("{}: the attributes of '{}' ({}) are corrupt: checksum {:08x}, stored {:08x}",
                    file_name(obj), where, covered, actual, stored));
  }
  return true;
}

void write_text(hid_t parent, const std::string& name, std::string_view text) {
  Handle type{check(H5Tcopy(H5T_C_S1), parent, "copy string type for", name), H5Tclose};
  check(H5Tset_size(type.get(), std::max<std::size_t>(text.size(), 1)), parent, "size", name);
  check(H5Tset_strpad(type.get(), H5T_STR_NULLPAD), parent, "pad string", name);
  Handle space{check(H5Screate(H5S_SCALAR), parent, "create dataspace for", name), H5Sclose};
  Handle dcpl = untimed(H5P_DATASET_CREATE);
  Handle set{check(H5Dcreate2(parent, name.c_str(), type.get(), space.get(), H5P_DEFAULT,
                              dcpl.get(), H5P_DEFAULT),
                   parent, "create dataset", name),
             H5Dclose};
  std::string buffer(text);
  if (buffer.empty()) buffer.push_back('\0');
  check(H5Dwrite(set.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer.data()), parent,
        "write", name);
  set_checksum(set.get(), parent, name, buffer.data(), buffer.size());
}

std::string read_text(hid_t parent, const std::string& name, Verify verify) {
  Handle set = open_dataset(parent, name);
  Handle type{check(H5Dget_type(set.get()), parent, "get type of", name), H5Tclose};
  if (H5Tget_class(type.get()) != H5T_STRING || H5Tis_variable_str(type.get()) > 0) {
    fail(parent, "read fixed-length text dataset", name);
  }
  std::string out(H5Tget_size(type.get()), '\0');
  check(H5Dread(set.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()), parent, "read",
        name);
  verify_checksum(set.get(), parent, name, out.data(), out.size(), verify);
  while (!out.empty() && out.back() == '\0') out.pop_back();
  return out;
}

std::string file_name(hid_t obj) {
  const ssize_t len = H5Fget_name(obj, nullptr, 0);
  if (len <= 0) return "<unknown file>";
  std::string name(static_cast<std::size_t>(len), '\0');
  H5Fget_name(obj, name.data(), name.size() + 1);
  return name;
}

}  // namespace shatter::io::h5

namespace shatter::io {

void skip_hdf5_shutdown_at_exit() {
  H5dont_atexit();
}

}  // namespace shatter::io
