#include "shatter/io/checkpoint.hpp"

#include <unordered_map>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <fmt/format.h>

#include "io/h5.hpp"
#include "io/particles_h5.hpp"

namespace shatter::io {
namespace {

constexpr std::string_view kFormat = "shatter checkpoint";
// 2: checksums, internal_next, dt_first. 3: the root attributes (format_version included) are
// sealed (h5::seal_attrs), so a changed format_version cannot switch the verification off.
constexpr std::uint64_t kFormatVersion = 3;
const std::vector<std::string> kRootAttrs = {"format", "format_version", "program_version",
                                             "checksums", "state_crc32"};

// The energy budget's members, written and read by one table so the two cannot drift apart.
constexpr std::pair<const char*, double EnergyBudget::*> kEnergyTerms[] = {
    {"kinetic", &EnergyBudget::kinetic},     {"internal", &EnergyBudget::internal},
    {"potential", &EnergyBudget::potential}, {"boundary_work", &EnergyBudget::boundary_work},
    {"outflow", &EnergyBudget::outflow},     {"initial", &EnergyBudget::initial},
    {"scale", &EnergyBudget::scale},
};

// The clock's and the output cursor's members, each written and read by one table, attributes
// of the groups "clock" and "output" in this order. Doubles are stored as native IEEE values, so
// a round trip is exact (restarts are bitwise).
template <class S>
using Member = std::variant<double S::*, std::uint64_t S::*>;
template <class S>
struct Attr {
  const char* name;
  Member<S> member;
};
constexpr Attr<Clock> kClockAttrs[] = {{"time", &Clock::time},
                                       {"dt", &Clock::dt},
                                       {"dt_prev", &Clock::dt_prev},
                                       {"step", &Clock::step}};
constexpr Attr<OutputCursor> kCursorAttrs[] = {
    {"next_snapshot", &OutputCursor::next_snapshot},
    {"next_snapshot_time", &OutputCursor::next_snapshot_time},
    {"next_checkpoint_time", &OutputCursor::next_checkpoint_time}};

template <class S, std::size_t N>
void write_attrs(hid_t file, const char* group, const S& s, const Attr<S> (&attrs)[N]) {
  h5::Handle g = h5::create_group(file, group);
  for (const Attr<S>& a : attrs) {
    std::visit([&](auto member) { h5::set_attr(g.get(), a.name, s.*member); }, a.member);
  }
}

void read_attr(hid_t obj, const char* name, double& v) {
  v = h5::get_attr_double(obj, name);
}
void read_attr(hid_t obj, const char* name, std::uint64_t& v) {
  v = h5::get_attr_u64(obj, name);
}

template <class S, std::size_t N>
S read_attrs(hid_t file, const char* group, const Attr<S> (&attrs)[N]) {
  h5::Handle g = h5::open_group(file, group);
  S s;
  for (const Attr<S>& a : attrs) {
    std::visit([&](auto member) { read_attr(g.get(), a.name, s.*member); }, a.member);
  }
  return s;
}

// The attribute values the checksums of the datasets do not cover, as bytes in a fixed order.
std::vector<unsigned char> state_bytes(const RunState& s) {
  std::vector<unsigned char> out;
  auto put = [&out](const auto& v) {
    const auto* p = reinterpret_cast<const unsigned char*>(&v);
    out.insert(out.end(), p, p + sizeof(v));
  };
  put(s.clock.time);
  put(s.clock.dt);
  put(s.clock.dt_prev);
  put(s.clock.step);
  for (const auto& [name, member] : kEnergyTerms) put(s.energy.*member);
  put(s.internal_next);
  put(s.dt_first);
  put(s.cursor.next_snapshot);
  put(s.cursor.next_snapshot_time);
  put(s.cursor.next_checkpoint_time);
  return out;
}

void write_energy(hid_t file, const EnergyBudget& e) {
  h5::Handle g = h5::create_group(file, "energy");
  h5::set_attr(g.get(), "units", std::string_view("J"));
  for (const auto& [name, member] : kEnergyTerms) h5::set_attr(g.get(), name, e.*member);
}

EnergyBudget read_energy(hid_t file) {
  h5::Handle g = h5::open_group(file, "energy");
  EnergyBudget e;
  for (const auto& [name, member] : kEnergyTerms) e.*member = h5::get_attr_double(g.get(), name);
  return e;
}

// Every column the saved store holds, real or integer, into the live store: live row p takes
// saved row (*from)[p], or row p where `from` is null (stores of the same rows).
template <class FieldEnum>
void copy_columns(ParticleStore& live, const ParticleStore& saved, std::size_t count,
                  const std::vector<std::size_t>* from) {
  for (std::size_t i = 0; i < count; ++i) {
    const auto f = static_cast<FieldEnum>(i);
    if (!saved.has(f)) continue;
    live.require(f);
    const auto src = saved.col(f);
    auto dst = live.col(f);
    if (from == nullptr) {
      std::copy(src.begin(), src.end(), dst.begin());
    } else {
      for (std::size_t p = 0; p < from->size(); ++p) dst[p] = src[(*from)[p]];
    }
  }
}

// The format version, trusted only when the root attributes' seal holds (format 3) or the file
// carries none of what a later format adds: a format-2 file whose version reads 1 would
// otherwise be resumed without verification.
std::uint64_t checked_version(hid_t f, const std::filesystem::path& file) {
  const bool sealed = h5::verify_attrs(f, kRootAttrs);
  const auto version = h5::get_attr_u64(f, "format_version");
  if (sealed ? version != kFormatVersion : version >= kFormatVersion || version == 0) {
    throw std::runtime_error(fmt::format(
        "{}: checkpoint format {}{} (this shatter reads 1 to {}): corrupt file?", file.string(),
        version, sealed ? "" : " without its attribute checksum", kFormatVersion));
  }
  if (version == 1 && (h5::has_attr(f, "state_crc32") || h5::has_attr(f, "checksums"))) {
    throw std::runtime_error(fmt::format(
        "{}: format_version says 1 but the file carries the checksums of format 2 or later: "
        "corrupt file",
        file.string()));
  }
  return version;
}

}  // namespace

void write_checkpoint(const std::filesystem::path& file, const ParticleStore& store,
                      const RunState& state, const CheckpointProgress& progress) {
  h5::QuietErrors quiet;
  h5::write_file_atomically(file, [&](hid_t f) {
    h5::set_attr(f, "format", kFormat);
    h5::set_attr(f, "format_version", kFormatVersion);
    h5::set_attr(f, "program_version", state.program_version);
    h5::set_attr(f, "checksums",
                 std::string_view("crc32 (zlib) of each dataset's values in its attribute "
                                  "crc32; state_crc32 covers clock, energy and output"));
    // A dataset, not an attribute: attributes are limited to 64 KiB in the default format.
    h5::write_text(f, "scene", state.scene_text);
    write_attrs(f, "clock", state.clock, kClockAttrs);
    write_energy(f, state.energy);
    write_attrs(f, "output", state.cursor, kCursorAttrs);
    {
      h5::Handle g = h5::open_group(f, "clock");
      h5::set_attr(g.get(), "dt_first", state.dt_first);
      h5::Handle e = h5::open_group(f, "energy");
      h5::set_attr(e.get(), "internal_next", state.internal_next);
    }
    const auto bytes = state_bytes(state);
    h5::set_attr(f, "state_crc32", h5::checksum(bytes.data(), bytes.size()));
    h5::seal_attrs(f, kRootAttrs);
    if (progress) progress("state");
    write_particles(f, store, all_columns(store), progress);
  });
}

Checkpoint read_checkpoint(const std::filesystem::path& file) {
  h5::QuietErrors quiet;
  h5::Handle f = h5::open_file(file);
  if (!h5::has_attr(f.get(), "format") || h5::get_attr_string(f.get(), "format") != kFormat) {
    throw std::runtime_error(fmt::format("{} is not a shatter checkpoint", file.string()));
  }
  const auto version = checked_version(f.get(), file);
  // Format 1 predates checksums: read as before, nothing to verify.
  const auto verify = version >= 2 ? h5::Verify::required : h5::Verify::if_present;
  Checkpoint c;
  c.state.program_version = h5::get_attr_string(f.get(), "program_version");
  c.state.scene_text = h5::read_text(f.get(), "scene", verify);
  c.state.clock = read_attrs(f.get(), "clock", kClockAttrs);
  c.state.energy = read_energy(f.get());
  c.state.cursor = read_attrs(f.get(), "output", kCursorAttrs);
  if (version >= 2) {
    h5::Handle g = h5::open_group(f.get(), "clock");
    c.state.dt_first = h5::get_attr_double(g.get(), "dt_first");
    h5::Handle e = h5::open_group(f.get(), "energy");
    c.state.internal_next = h5::get_attr_double(e.get(), "internal_next");
    const auto bytes = state_bytes(c.state);
    const auto stored = h5::get_attr_u64(f.get(), "state_crc32");
    const auto actual = h5::checksum(bytes.data(), bytes.size());
    if (stored != actual) {
      throw std::runtime_error(fmt::format(
          "{}: the clock/energy/output attributes are corrupt: checksum {:08x}, stored {:08x}",
          file.string(), actual, stored));
    }
  }
  c.particles = read_particles(f.get(), verify);
  return c;
}

void restore_columns(ParticleStore& live, const ParticleStore& saved) {
  // A store of the checkpoint's size takes its rows in the saved order, as before MPI: the SPH
  // solver's sums follow the store order, so a resumed run continues bitwise only in that order
  // (the MPM step does not depend on it: docs/mpi.md, "Determinism").
  const bool by_id = live.has(IField::id) && saved.has(IField::id) &&
                     live.groups().size() == saved.groups().size() && live.size() != saved.size();
  if (by_id) {
    // One rank's share of the checkpoint (docs/mpi.md): rows matched by particle id.
    std::unordered_map<std::int64_t, std::size_t> row;
    const auto sid = saved.col(IField::id);
    row.reserve(sid.size());
    for (std::size_t p = 0; p < sid.size(); ++p) row.emplace(sid[p], p);
    const auto lid = live.col(IField::id);
    std::vector<std::size_t> from(live.size());
    for (std::size_t p = 0; p < live.size(); ++p) {
      const auto it = row.find(lid[p]);
      if (it == row.end()) throw std::logic_error("restore_columns: a particle id not saved");
      from[p] = it->second;
    }
    copy_columns<Field>(live, saved, kFieldCount, &from);
    copy_columns<IField>(live, saved, kIFieldCount, &from);
    return;
  }
  if (live.size() != saved.size() || live.groups().size() != saved.groups().size()) {
    throw std::logic_error("restore_columns: the stores hold different particles");
  }
  copy_columns<Field>(live, saved, kFieldCount, nullptr);
  copy_columns<IField>(live, saved, kIFieldCount, nullptr);
}

}  // namespace shatter::io
