#include "mpm/transfer.hpp"

#include <stdexcept>

#include <fmt/format.h>

namespace shatter::mpm {
namespace {

// The filter-heat booking needs an update that filters: plain FLIP removes nothing, and APIC's
// affine velocity C_p keeps part of what its PIC update drops, which the FLIP-minus-filtered
// difference would book as heat a second time.
void check_filter_heat(const SolverConfig& c) {
  const bool filters = c.transfer == TransferKind::xpic || c.transfer == TransferKind::fmpm ||
                       (c.transfer == TransferKind::flip && c.pic_fraction > 0.0);
  if (!filters) {
    throw std::invalid_argument(fmt::format(
        "solver: filter_heat applies only to a filtering transfer (xpic, fmpm, or flip with "
        "pic_fraction > 0), not '{}' with pic_fraction {}",
        name_of(c.transfer), c.pic_fraction));
  }
}

void check(const SolverConfig& c) {
  if (c.transfer == TransferKind::apic && c.shape == ShapeKind::linear) {
    // C_p = sum v_I grad N_I^T jumps when a point crosses a cell face with linear shapes; the
    // colliding-sphere test diverges within 50 steps. Jiang et al. (2015) use smooth kernels.
    throw std::invalid_argument(
        "solver: transfer 'apic' needs a smooth shape function (ugimp or bspline2), not 'linear'");
  }
  if (!(c.pic_fraction >= 0.0 && c.pic_fraction <= 1.0)) {
    throw std::invalid_argument(
        fmt::format("solver: pic_fraction must be in [0, 1], got {}", c.pic_fraction));
  }
  if (c.pic_fraction != 0.0 && c.transfer != TransferKind::flip) {
    throw std::invalid_argument(fmt::format(
        "solver: pic_fraction applies only to transfer 'flip' (the FLIP/PIC blend), not '{}'",
        name_of(c.transfer)));
  }
  // Orders past ~40 are unstable (Hammerquist & Nairn 2017; each order is one more
  // grid-particle-grid pass), and the binomial weights C(m, k) lose precision.
  constexpr int kMaxXpicOrder = 32;
  if (c.transfer == TransferKind::xpic && (c.xpic_order < 1 || c.xpic_order > kMaxXpicOrder)) {
    throw std::invalid_argument(
        fmt::format("solver: xpic_order must be in [1, {}], got {}", kMaxXpicOrder, c.xpic_order));
  }
  // FMPM(k): the same passes as XPIC, so the same bound; Nairn (2026, arXiv 2604.07307) finds
  // high orders need smaller time steps, so large k is for study, not production.
  constexpr int kMaxFmpmOrder = 32;
  if (c.transfer == TransferKind::fmpm && (c.fmpm_order < 1 || c.fmpm_order > kMaxFmpmOrder)) {
    throw std::invalid_argument(
        fmt::format("solver: fmpm_order must be in [1, {}], got {}", kMaxFmpmOrder, c.fmpm_order));
  }
  if (c.filter_every < 1) {
    throw std::invalid_argument(
        fmt::format("solver: filter_every must be >= 1, got {}", c.filter_every));
  }
  if (c.filter_every != 1 && c.transfer != TransferKind::xpic && c.transfer != TransferKind::fmpm) {
    // APIC's C_p and the blend's fraction act on every step; a FLIP step would drop C_p.
    throw std::invalid_argument(
        fmt::format("solver: filter_every applies only to transfer 'xpic' or 'fmpm', not '{}'",
                    name_of(c.transfer)));
  }
  if (c.filter_heat) check_filter_heat(c);
}

}  // namespace

TransferPolicy TransferPolicy::from(const SolverConfig& c) {
  check(c);
  TransferPolicy t;
  t.kind = c.transfer;
  t.affine = c.transfer == TransferKind::apic;
  t.remap = !t.affine;
  t.order = c.transfer == TransferKind::xpic   ? c.xpic_order
            : c.transfer == TransferKind::fmpm ? c.fmpm_order
                                               : 1;
  t.filter_every = c.filter_every;
  t.pic_fraction = c.pic_fraction;
  t.filter_heat = c.filter_heat;
  return t;
}

}  // namespace shatter::mpm
