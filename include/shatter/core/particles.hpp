#pragma once
// ParticleStore: material points as an entity-component store with structure-of-arrays columns
// (DESIGN.md, "Data"). Columns are 64-byte aligned; only registered columns exist. Particles of
// one material group occupy one contiguous range, so each group's constitutive kernel runs over
// plain column slices.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <xsimd/config/xsimd_config.hpp>
#include <xsimd/memory/xsimd_aligned_allocator.hpp>

#include "shatter/core/fields.hpp"

namespace shatter {

template <class T>
using AlignedVector = std::vector<T, xsimd::aligned_allocator<T, 64>>;

// A half-open index range [begin, end) of particles.
struct Range {
  std::size_t begin = 0;
  std::size_t end = 0;
  constexpr std::size_t size() const { return end - begin; }
  constexpr bool empty() const { return end == begin; }
};

// One material group: a contiguous range of particles sharing one constitutive model.
struct Group {
  Range range;
  int material = 0;  // index into the simulation's material list
};

class ParticleStore;

// Told of every change to a store's layout while attached to it (ParticleStore::attach): a
// re-order, a removal, a replacement. The MPM step retake keeps one (src/mpm/retake.hpp), so
// that a retaken step undoes what the attempt did, and no stage holds retake code.
class LayoutJournal {
 public:
  virtual ~LayoutJournal() = default;
  // After permute(order).
  virtual void permuted(std::span<const std::uint32_t> order) = 0;
  // Before remove_if(flags) removes at least one particle.
  virtual void removing(const ParticleStore& store, std::span<const std::uint8_t> flags) = 0;
  // Before replace(): the store as it is; the journal may move from it.
  virtual void replacing(ParticleStore& before) = 0;
  // After swap_column(f, buffer): `previous`, the caller's buffer, now holds the column's values
  // from before the swap.
  virtual void swapped(Field f, AlignedVector<double>& previous) = 0;
};

class ParticleStore {
 public:
  // Registers a column (zero-filled at the current size). Registering twice is harmless.
  void require(Field f);
  void require(IField f);
  void require(FieldSet fields);
  bool has(Field f) const { return present_[index(f)]; }
  bool has(IField f) const { return ipresent_[index(f)]; }
  FieldSet registered() const;

  std::size_t size() const { return size_; }

  // Appends n zero-initialised particles as a new group with the given material index; returns
  // its range. Groups are only ever appended, so earlier ranges stay valid.
  Range add_group(int material, std::size_t n);
  const std::vector<Group>& groups() const { return groups_; }

  // Column access; throws std::logic_error naming the field if it was not registered.
  std::span<double> col(Field f);
  std::span<const double> col(Field f) const;
  std::span<std::int64_t> col(IField f);
  std::span<const std::int64_t> col(IField f) const;

  // Reorders every registered column: new particle k is old particle order[k]. The permutation
  // must map each group range onto itself (the sort stage sorts within groups). Each column is
  // gathered into a spare column, whose buffer it then takes: the store's own, or `spare` (any
  // content, resized to the store; it ends holding one of the old buffers), so that a caller
  // with a dead buffer of its own needs no second one here.
  void permute(std::span<const std::uint32_t> order);
  void permute(std::span<const std::uint32_t> order, AlignedVector<double>& spare);

  // Exchanges column f's buffer with `buffer` (of the store's size), no copy: the column then
  // holds what `buffer` held, and `buffer` the column's values (a stage that writes a whole
  // new column into a buffer of its own, and keeps the old values there).
  void swap_column(Field f, AlignedVector<double>& buffer);

  // Removes the particles whose flag is non-zero, keeping the order of the rest and the
  // grouping (groups shrink). Returns how many were removed.
  std::size_t remove_if(std::span<const std::uint8_t> flags);

  // Replaces the whole store by `next` (particle migration), telling the journal first.
  void replace(ParticleStore&& next);

  // Attaches a layout journal (nullptr: none). The attachment belongs to this store object:
  // copies and assignments neither carry it to another store nor drop it from this one.
  void attach(LayoutJournal* journal) { journal_.to = journal; }

 private:
  struct Attached {
    LayoutJournal* to = nullptr;
    Attached() = default;
    Attached(const Attached&) {}
    Attached& operator=(const Attached&) { return *this; }
  };

  static constexpr std::size_t index(Field f) { return static_cast<std::size_t>(f); }
  static constexpr std::size_t index(IField f) { return static_cast<std::size_t>(f); }
  void resize(std::size_t n);

  std::size_t size_ = 0;
  std::array<AlignedVector<double>, kFieldCount> cols_{};
  std::array<AlignedVector<std::int64_t>, kIFieldCount> icols_{};
  std::array<bool, kFieldCount> present_{};
  std::array<bool, kIFieldCount> ipresent_{};
  std::vector<Group> groups_;
  AlignedVector<double> scratch_;  // permute's spare column (the integer ones go through it too)
  Attached journal_;
};

// Typed access for a stage that declared the fields it reads (R) and writes (W). Asking for a
// field outside the declaration is a compile error, so a stage's data needs are its signature.
template <FieldSet R, FieldSet W>
class Columns {
 public:
  static constexpr FieldSet kReads = R;
  static constexpr FieldSet kWrites = W;

  explicit Columns(ParticleStore& store) : store_(&store) {}

  template <Field F>
  const double* in() const {
    static_assert(R.has(F) || W.has(F), "stage reads a field it did not declare");
    return store_->col(F).data();
  }
  template <Field F>
  double* out() const {
    static_assert(W.has(F), "stage writes a field it did not declare");
    return store_->col(F).data();
  }
  std::size_t size() const { return store_->size(); }

 private:
  ParticleStore* store_;
};

}  // namespace shatter
