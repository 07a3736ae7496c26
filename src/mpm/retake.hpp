#pragma once
// The step retake (Simulation::step): the state before the step being taken, to take it again,
// and a journal of what the attempt under way did to the store's layout (re-order, outflow,
// migration), which the restore undoes. The store itself tells the journal of each change
// (LayoutJournal), so the stages hold no retake code.

#include <array>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "shatter/core/energy.hpp"
#include "shatter/core/fields.hpp"
#include "shatter/core/particles.hpp"
#include "shatter/core/solver.hpp"

namespace shatter::mpm {

struct State;

// What the step retake need not save. Constant: no stage writes these columns (mass, reference
// volume and size of the material point, and its flaw population: the damage models read
// eps_min, eps_max, n_flaws and weibull_m and store them back unchanged), nor the integer
// columns (id, body, fragment). Step-local: each step writes them for every particle before
// any stage reads them: the strain and spin increments (which the engine keeps out of the
// store since issue 35; a store restored from an older checkpoint may still hold them, unread),
// and pressure and sound speed, which MaterialModel::update sets for step n+1 from the rest of
// the state (its contract; the time-step and energy stages read them after it). Every other
// registered column is saved, so a column added later is saved unless it is listed here.
constexpr FieldSet kStepConstant{Field::mass,    Field::volume0, Field::size0,    Field::eps_min,
                                 Field::eps_max, Field::n_flaws, Field::weibull_m};
constexpr FieldSet kStepLocal =
    kStrainIncrement | kSpinIncrement | FieldSet{Field::pressure, Field::soundspeed};
// Not saved either: the positions. No stage writes them in place; advance_positions exchanges
// their buffers with the displacement scratch's (ParticleStore::swap_column), which then holds
// x^n, and the restore exchanges them back (the journal is told of each exchange).
constexpr FieldSet kSwappedOut = kPosition;
// Columns the step's finite check reads (check_finite) that the retake's copy always holds (none
// of them constant, step-local or swapped out): the copy tests them as it reads them, so that the
// sort stage's check need not read them a second time (Journal::save_columns).
constexpr FieldSet kCheckedByCopy = kVelocity | kStress | FieldSet{Field::rho, Field::energy};
// The finite test both the copy and check_finite make: 1 when the value's exponent bits are all
// set (IEEE 754: an infinity or a NaN). OR-ed over a chunk, it has no branch per element and
// vectorises.
inline std::uint64_t not_finite_bits(std::uint64_t w) {
  constexpr std::uint64_t kExponent = 0x7ff0000000000000ULL;
  return static_cast<std::uint64_t>((w & kExponent) == kExponent);
}
static_assert([] {
  for (std::size_t i = 0; i < kFieldCount; ++i) {
    const auto f = static_cast<Field>(i);
    if (kCheckedByCopy.has(f) &&
        (kStepConstant.has(f) || kStepLocal.has(f) || kSwappedOut.has(f))) {
      return false;
    }
  }
  return true;
}());
//
// When: the groups, clock and accounts before the first attempt (save); the columns in the
// first attempt, at the end of the sort stage (save_columns, called there), so the copy is in
// the sorted order and a retake keeps the sort's re-order instead of undoing it.
// The retaken attempt's sort then leaves the order as it is (a stable sort of keys already
// sorted within each group is the identity), and every later stage sees the same store as in
// an attempt from the unsorted one: the same bits, with no permutation kept for the retake
// (4 B per particle).

class Journal final : public LayoutJournal {
 public:
  // Before the first attempt: the groups, clock and accounts; the columns are then due.
  void save(const State& s);
  // In the first attempt, after the sort: the columns the step writes (see "When" above). The
  // first goes into `lent`'s buffer (the owner keys, dead from there to the step's end: 8 B per
  // point less), which end_step gives back. Returns false when a copied value is not finite
  // (its exponent bits all set), tested as it is copied: the columns kCheckedByCopy are among
  // them.
  bool save_columns(const ParticleStore& P, std::vector<std::uint64_t>& lent);
  bool columns_due() const { return columns_due_; }
  // Before each attempt: when it may be retaken, the journal attaches to the store and records
  // the layout changes the stages make (ParticleStore tells it).
  void begin_attempt(ParticleStore& P, bool may_retake);
  // The state at t^n again, with every layout change of the attempt undone.
  void restore(State& s);
  // After the last attempt: detached; a store migration replaced is freed; the buffer lent by
  // save_columns back to `lent`.
  void end_step(ParticleStore& P, std::vector<std::uint64_t>& lent);

  // LayoutJournal: outflow's removal, migration's replacement; the sort stage's re-order is
  // kept (see "When"), and a re-order after the columns were saved must be the identity.
  void permuted(std::span<const std::uint32_t> order) override;
  void removing(const ParticleStore& P, std::span<const std::uint8_t> leaving) override;
  void replacing(ParticleStore& before) override;
  // advance_positions' exchange of a position column with its displacement buffer.
  void swapped(Field f, AlignedVector<double>& previous) override;

  // Wall time of the restores (and of save's few scalars); the columns' copy is timed with the
  // sort stage, whose end makes it.
  StageTiming timing{"retake_copy", 0.0};

 private:
  bool saves(const ParticleStore& P, Field f) const;
  void undo_outflow(ParticleStore& P) const;

  std::vector<Field> fields_;  // registered columns the step writes
  // Their values at t^n, in the order of `fields_`, as 8-byte words (copied, not converted), so
  // that the first can live in the owner keys' buffer.
  std::vector<std::vector<std::uint64_t>> cols_;
  std::vector<Group> groups_;  // the groups at t^n
  Clock clock_;
  EnergyBudget energy_;
  double internal_next_ = 0.0;
  bool columns_due_ = false;  // save_columns not yet called in this step
  bool lent_out_ = false;     // cols_[0] is the owner keys' buffer (save_columns, end_step)
  // The columns exchanged with a buffer, which holds their values at the exchange, in order.
  std::vector<std::pair<Field, AlignedVector<double>*>> swaps_;
  // Outflow removed the particles flagged here (over the store before the removal; empty:
  // none); their unsaved columns, in store order.
  std::vector<std::uint8_t> left_;
  std::array<std::vector<double>, kFieldCount> left_rows_;
  std::array<std::vector<std::int64_t>, kIFieldCount> left_irows_;
  bool whole_ = false;   // migration moved particles; `store_` is the whole store at t^n
  ParticleStore store_;  // (the store migration replaced, moved here rather than freed)
};

}  // namespace shatter::mpm
