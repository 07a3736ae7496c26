#include "mpm/retake.hpp"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cstring>
#include <stdexcept>
#include <utility>

#include <tbb/parallel_for.h>

#include "mpm/state.hpp"

namespace shatter::mpm {
namespace {

// Copies n values of `columns` columns in parallel chunks: copy(column, begin, end).
template <class Copy>
void copy_columns(std::size_t columns, std::size_t n, Copy&& copy) {
  constexpr std::size_t kGrain = 16384;  // 128 KiB of doubles
  const std::size_t chunks = (n + kGrain - 1) / kGrain;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, columns * chunks),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t k = r.begin(); k < r.end(); ++k) {
                        const std::size_t c = k / chunks, b = (k % chunks) * kGrain;
                        copy(c, b, std::min(b + kGrain, n));
                      }
                    });
}

}  // namespace

bool Journal::saves(const ParticleStore& P, Field f) const {
  return P.has(f) && !kStepConstant.has(f) && !kStepLocal.has(f) && !kSwappedOut.has(f);
}

void Journal::save(const State& s) {
  groups_ = s.particles.groups();
  clock_ = s.clock;
  energy_ = s.energy;
  internal_next_ = s.internal_next;
  columns_due_ = true;
}

bool Journal::save_columns(const ParticleStore& P, std::vector<std::uint64_t>& lent) {
  columns_due_ = false;
  const std::size_t n = P.size();
  fields_.clear();
  for (std::size_t i = 0; i < kFieldCount; ++i) {
    if (saves(P, static_cast<Field>(i))) fields_.push_back(static_cast<Field>(i));
  }
  cols_.resize(fields_.size());
  if (!cols_.empty()) {
    cols_[0] = std::move(lent);  // given back by end_step
    lent_out_ = true;
  }
  for (auto& c : cols_) c.resize(n);  // reuses the buffers of the last step
  // The copy word by word (the same bits), with the finite test of check_finite OR-ed over what
  // it reads: no branch per value, and it vectorises as memcpy's loop does.
  std::atomic<bool> finite{true};
  copy_columns(fields_.size(), n, [&](std::size_t c, std::size_t b, std::size_t e) {
    const double* src = P.col(fields_[c]).data();
    std::uint64_t* dst = cols_[c].data();
    std::uint64_t bad = 0;
    for (std::size_t p = b; p < e; ++p) {
      const auto w = std::bit_cast<std::uint64_t>(src[p]);
      dst[p] = w;
      bad |= not_finite_bits(w);
    }
    if (bad != 0) finite.store(false, std::memory_order_relaxed);
  });
  return finite.load(std::memory_order_relaxed);
}

void Journal::begin_attempt(ParticleStore& P, bool may_retake) {
  P.attach(may_retake ? this : nullptr);
  swaps_.clear();
  whole_ = false;
  left_.clear();
}

void Journal::end_step(ParticleStore& P, std::vector<std::uint64_t>& lent) {
  P.attach(nullptr);
  // The owner keys' buffer back (a retaken attempt's sort gave the keys a new one meanwhile,
  // freed here).
  if (lent_out_) lent = std::move(cols_[0]);
  lent_out_ = false;
  store_ = ParticleStore{};  // a store migration replaced is freed, as it was before
}

void Journal::permuted(std::span<const std::uint32_t> order) {
  // The first attempt's sort (kept on a retake), or a store migration replaced (restored whole).
  if (columns_due_ || whole_) return;
  // A retaken attempt's sort (keys already sorted: the identity). Anything else would leave
  // the saved columns in another order than the store's.
  for (std::size_t k = 0; k < order.size(); ++k) {
    if (order[k] != k)
      throw std::logic_error("step retake: the store was re-ordered after its save");
  }
}

void Journal::restore(State& s) {
  ParticleStore& P = s.particles;
  P.attach(nullptr);  // the undoing is not an attempt's change
  if (whole_) {
    P = store_;  // taken before migration moved anything: the store at t^n
  } else {
    // Undo in the reverse order of the step: the outflow removal, then the exchanges of the
    // position buffers (the store has its size before the removal again, the buffers' size).
    // The sort's re-order stays (see "When" in retake.hpp).
    if (!left_.empty()) undo_outflow(P);
    for (auto it = swaps_.rbegin(); it != swaps_.rend(); ++it)
      P.swap_column(it->first, *it->second);
    copy_columns(fields_.size(), P.size(), [&](std::size_t c, std::size_t b, std::size_t e) {
      if (e > b) std::memcpy(P.col(fields_[c]).data() + b, cols_[c].data() + b, (e - b) * 8);
    });
  }
  s.clock = clock_;
  s.energy = energy_;
  s.internal_next = internal_next_;
}

void Journal::removing(const ParticleStore& P, std::span<const std::uint8_t> leaving) {
  if (whole_) return;  // the store at t^n is kept whole
  left_.assign(leaving.begin(), leaving.end());
  for (std::size_t i = 0; i < kFieldCount; ++i) {
    const auto f = static_cast<Field>(i);
    left_rows_[i].clear();
    if (!P.has(f) || saves(P, f)) continue;
    const auto c = P.col(f);
    for (std::size_t p = 0; p < leaving.size(); ++p) {
      if (leaving[p]) left_rows_[i].push_back(c[p]);
    }
  }
  for (std::size_t i = 0; i < kIFieldCount; ++i) {
    const auto f = static_cast<IField>(i);
    left_irows_[i].clear();
    if (!P.has(f)) continue;
    const auto c = P.col(f);
    for (std::size_t p = 0; p < leaving.size(); ++p) {
      if (leaving[p]) left_irows_[i].push_back(c[p]);
    }
  }
}

void Journal::swapped(Field f, AlignedVector<double>& previous) {
  swaps_.emplace_back(f, &previous);
}

void Journal::replacing(ParticleStore& before) {
  store_ = std::move(before);  // the store at t^n, for a retake; kept rather than freed
  whole_ = true;
}

// The store as it was before outflow's removal (the columns restore copies back are left zero
// here): the departed particles' rows merged back in their places.
void Journal::undo_outflow(ParticleStore& P) const {
  const std::vector<std::uint8_t>& left = left_;
  ParticleStore B;
  B.require(P.registered());
  for (std::size_t i = 0; i < kIFieldCount; ++i) {
    if (P.has(static_cast<IField>(i))) B.require(static_cast<IField>(i));
  }
  for (const Group& g : groups_) B.add_group(g.material, g.range.size());
  const auto merge = [&](auto dst, auto src, const auto& rows) {
    std::size_t k = 0, j = 0;
    for (std::size_t p = 0; p < left.size(); ++p) dst[p] = left[p] ? rows[j++] : src[k++];
  };
  for (std::size_t i = 0; i < kFieldCount; ++i) {
    const auto f = static_cast<Field>(i);
    if (P.has(f) && !saves(P, f)) merge(B.col(f), std::as_const(P).col(f), left_rows_[i]);
  }
  for (std::size_t i = 0; i < kIFieldCount; ++i) {
    const auto f = static_cast<IField>(i);
    if (P.has(f)) merge(B.col(f), std::as_const(P).col(f), left_irows_[i]);
  }
  P = std::move(B);
}

}  // namespace shatter::mpm
