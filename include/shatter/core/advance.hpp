#pragma once
// The clock loop both methods share (DESIGN.md "src/core ... clock (advance_to)"): steps until the
// clock reaches t, the last step shortened to land on t exactly.

#include "shatter/core/solver.hpp"

namespace shatter {

// Calls step() until clock.time reaches t; a step that would overshoot is shortened to end at t.
// A remainder below kSliver of the stable step is merged into the previous step (the clock jumps
// to t) rather than taken alone, so output times do not produce sliver steps.
template <class Step>
void advance_clock_to(Clock& clock, double t, Step&& step) {
  constexpr double kSliver = 1e-3;
  while (clock.time < t) {
    const double remaining = t - clock.time;
    if (remaining <= kSliver * clock.dt) {
      clock.time = t;
      break;
    }
    if (clock.dt > remaining) clock.dt = remaining;
    step();
  }
}

}  // namespace shatter
