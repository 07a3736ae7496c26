#include "mpm/transfer.hpp"

namespace shatter::mpm {

TransferPolicy TransferPolicy::from(const SolverConfig& c) {
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
