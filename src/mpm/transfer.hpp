#pragma once
// The transfer scheme (TransferKind), decided once when the solver is built: which stages the
// step has and what each transfer does, as plain data the stages read. The configuration is
// checked once, where it is read: the scene (src/scene/parse_solver.cpp) refuses a combination
// no policy implements, naming the key and its line; TransferPolicy::from trusts it.

#include <cstdint>

#include "shatter/core/config.hpp"

namespace shatter::mpm {

struct TransferPolicy {
  TransferKind kind = TransferKind::flip;
  // APIC (Jiang et al. 2015): the particles carry C_p, P2G scatters the affine momentum and
  // the velocity-gradient stage stores C_p; APIC particles hold the grid velocity already, so
  // the MUSL remap would return it unchanged and is left out of the step.
  bool affine = false;
  bool remap = true;
  // XPIC(m) or FMPM(k): the order m (k); a filter stage ("xpic" or "fmpm") makes its m - 1
  // extra grid-particle-grid passes every filter_every-th step when m > 1.
  int order = 1;
  int filter_every = 1;
  double pic_fraction = 0.0;  // FLIP: the share of the grid velocity (the FLIP/PIC blend)
  // Book the kinetic energy the filtered update removes as heat (SolverConfig::filter_heat;
  // the filter_heat stage, stages/filter_heat.cpp).
  bool filter_heat = false;

  // The policy of a configuration the scene has validated (parse_solver.cpp's transfer rules:
  // apic needs a smooth shape, pic_fraction in [0, 1] and flip only, xpic_order and fmpm_order
  // in [1, 32], filter_every >= 1 for xpic and fmpm only, filter_heat with a filtering transfer).
  static TransferPolicy from(const SolverConfig& c);

  // The step has a filter stage: XPIC or FMPM of order 2 or more (order 1 is PIC, bitwise).
  bool filter_stage() const {
    return (kind == TransferKind::xpic || kind == TransferKind::fmpm) && order > 1;
  }
  const char* filter_name() const { return kind == TransferKind::xpic ? "xpic" : "fmpm"; }
  // XPIC's G2P takes the filter stage's V*_m + a dt as the grid velocity of the update (FMPM
  // leaves v_F in the momentum arrays instead).
  bool filtered_target(bool filtering) const {
    return kind == TransferKind::xpic && filter_stage() && filtering;
  }
  // Periodic filtering (the PeriodicXPIC custom task of NairnMPM/OSParticulas: FLIP on most
  // steps, the XPIC(k) or FMPM(k) update every N-th): the step that leaves Clock::step = n + 1
  // filters when n + 1 is a multiple of N. The counter is in the checkpoint, so a resumed run
  // keeps the phase; a retaken step has the same counter, so it decides the same way.
  bool filters_step(std::uint64_t step) const {
    return (step + 1) % static_cast<std::uint64_t>(filter_every) == 0;
  }
  // The share of the filtered grid velocity in the G2P particle update.
  double filtered_share(bool filtering) const {
    switch (kind) {
      case TransferKind::flip:
        return pic_fraction;
      case TransferKind::apic:
        return 1.0;
      case TransferKind::xpic:
      case TransferKind::fmpm:
        return filtering ? 1.0 : 0.0;  // FLIP on the steps filter_every leaves out
    }
    return 0.0;
  }
};

}  // namespace shatter::mpm
