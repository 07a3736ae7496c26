#include "shatter/core/particles.hpp"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

namespace shatter {

void ParticleStore::require(Field f) {
  if (present_[index(f)]) return;
  present_[index(f)] = true;
  cols_[index(f)].assign(size_, 0.0);
}

void ParticleStore::require(IField f) {
  if (ipresent_[index(f)]) return;
  ipresent_[index(f)] = true;
  icols_[index(f)].assign(size_, 0);
}

void ParticleStore::require(FieldSet fields) {
  for (std::size_t i = 0; i < kFieldCount; ++i) {
    if (fields.has(static_cast<Field>(i))) require(static_cast<Field>(i));
  }
}

FieldSet ParticleStore::registered() const {
  FieldSet s;
  for (std::size_t i = 0; i < kFieldCount; ++i) {
    if (present_[i]) s = s.with(static_cast<Field>(i));
  }
  return s;
}

void ParticleStore::resize(std::size_t n) {
  for (std::size_t i = 0; i < kFieldCount; ++i) {
    if (present_[i]) cols_[i].resize(n, 0.0);
  }
  for (std::size_t i = 0; i < kIFieldCount; ++i) {
    if (ipresent_[i]) icols_[i].resize(n, 0);
  }
  size_ = n;
}

Range ParticleStore::add_group(int material, std::size_t n) {
  const Range r{size_, size_ + n};
  resize(size_ + n);
  groups_.push_back({r, material});
  return r;
}

std::span<double> ParticleStore::col(Field f) {
  if (!present_[index(f)]) {
    throw std::logic_error(fmt::format("particle field '{}' is not registered", name_of(f)));
  }
  return {cols_[index(f)].data(), size_};
}

std::span<const double> ParticleStore::col(Field f) const {
  return const_cast<ParticleStore*>(this)->col(f);  // NOLINT: same checks, read-only view
}

std::span<std::int64_t> ParticleStore::col(IField f) {
  if (!ipresent_[index(f)]) {
    throw std::logic_error(fmt::format("particle field '{}' is not registered", name_of(f)));
  }
  return {icols_[index(f)].data(), size_};
}

std::span<const std::int64_t> ParticleStore::col(IField f) const {
  return const_cast<ParticleStore*>(this)->col(f);  // NOLINT: same checks, read-only view
}

void ParticleStore::permute(std::span<const std::uint32_t> order) {
  permute(order, scratch_);
}

void ParticleStore::permute(std::span<const std::uint32_t> order, AlignedVector<double>& spare) {
  if (order.size() != size_) throw std::logic_error("permutation size differs from store size");
  spare.resize(size_);
  for (std::size_t i = 0; i < kFieldCount; ++i) {
    if (!present_[i]) continue;
    const double* src = cols_[i].data();
    for (std::size_t k = 0; k < size_; ++k) spare[k] = src[order[k]];
    cols_[i].swap(spare);
  }
  // The integer columns through the same spare, as 8-byte patterns (no conversion), then copied
  // back: one pass more than a spare integer column of their own, 8 B per particle less.
  for (std::size_t i = 0; i < kIFieldCount; ++i) {
    if (!ipresent_[i]) continue;
    std::int64_t* col = icols_[i].data();
    for (std::size_t k = 0; k < size_; ++k) std::memcpy(&spare[k], &col[order[k]], sizeof(double));
    if (size_ > 0) std::memcpy(col, spare.data(), size_ * sizeof(double));
  }
  if (journal_.to != nullptr) journal_.to->permuted(order);
}

void ParticleStore::swap_column(Field f, AlignedVector<double>& buffer) {
  if (!present_[index(f)]) {
    throw std::logic_error(fmt::format("particle field '{}' is not registered", name_of(f)));
  }
  if (buffer.size() != size_) throw std::logic_error("swapped buffer size differs from store size");
  cols_[index(f)].swap(buffer);
  if (journal_.to != nullptr) journal_.to->swapped(f, buffer);
}

void ParticleStore::replace(ParticleStore&& next) {
  if (journal_.to != nullptr) journal_.to->replacing(*this);
  *this = std::move(next);
}

std::size_t ParticleStore::remove_if(std::span<const std::uint8_t> flags) {
  if (flags.size() != size_) throw std::logic_error("removal mask size differs from store size");
  if (journal_.to != nullptr &&
      std::any_of(flags.begin(), flags.end(), [](std::uint8_t f) { return f != 0; })) {
    journal_.to->removing(*this, flags);
  }
  std::vector<std::uint32_t> keep;
  keep.reserve(size_);
  for (auto& g : groups_) {
    const std::size_t new_begin = keep.size();
    for (std::size_t p = g.range.begin; p < g.range.end; ++p) {
      if (!flags[p]) keep.push_back(static_cast<std::uint32_t>(p));
    }
    g.range = {new_begin, keep.size()};
  }
  const std::size_t removed = size_ - keep.size();
  if (removed == 0) return 0;
  for (std::size_t i = 0; i < kFieldCount; ++i) {
    if (!present_[i]) continue;
    auto& c = cols_[i];
    for (std::size_t k = 0; k < keep.size(); ++k) c[k] = c[keep[k]];
    c.resize(keep.size());
  }
  for (std::size_t i = 0; i < kIFieldCount; ++i) {
    if (!ipresent_[i]) continue;
    auto& c = icols_[i];
    for (std::size_t k = 0; k < keep.size(); ++k) c[k] = c[keep[k]];
    c.resize(keep.size());
  }
  size_ = keep.size();
  return removed;
}

}  // namespace shatter
