#pragma once
// An exact, order-independent sum of doubles (a fixed-point "superaccumulator" over the whole
// double range). Energy sums over particles use it so that the reported value has the same bits
// whichever rank holds a particle, in whichever order a rank holds its particles, and however
// TBB splits the loop (docs/mpi.md, "Determinism"). Each double m 2^e is split into 32-bit
// limbs of one 2098-bit fixed-point number; limbs are int64, so up to 2^31 terms can be added
// before normalise() must carry. Two accumulators add limb by limb (exact), and across ranks
// with one MPI_Allreduce of the limbs. value() rounds the normalised (unique) representation,
// so equal exact sums give equal doubles.

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace shatter::parallel {

__extension__ using U128 = unsigned __int128;

class ExactSum {
 public:
  // 2^-1074 (smallest subnormal) .. 2^1024: 2098 bits, 66 limbs, plus carry room.
  static constexpr int kLimbs = 68;
  static constexpr int kBias = 1074;

  void add(double v) {
    const auto bits = std::bit_cast<std::uint64_t>(v);
    const int exp = static_cast<int>((bits >> 52) & 0x7ff);
    if (exp == 0x7ff) {  // inf or NaN: kept aside, and value() returns it
      special_ += v;
      return;
    }
    std::uint64_t mant = bits & ((std::uint64_t{1} << 52) - 1);
    int e = exp - 1075;  // v = mant 2^e
    if (exp == 0) {
      e = -1074;
    } else {
      mant |= std::uint64_t{1} << 52;
    }
    if (mant == 0) return;
    const int pos = e + kBias;  // bit position of mant's lowest bit, >= 0
    const int limb = pos >> 5;
    const int shift = pos & 31;
    // mant << shift spans up to 85 bits: three 32-bit limbs.
    const U128 wide = static_cast<U128>(mant) << shift;
    const auto lo = static_cast<std::int64_t>(static_cast<std::uint64_t>(wide) & 0xffffffffu);
    const auto mid =
        static_cast<std::int64_t>(static_cast<std::uint64_t>(wide >> 32) & 0xffffffffu);
    const auto hi = static_cast<std::int64_t>(static_cast<std::uint64_t>(wide >> 64));
    if (bits >> 63) {
      limbs_[limb] -= lo;
      limbs_[limb + 1] -= mid;
      limbs_[limb + 2] -= hi;
    } else {
      limbs_[limb] += lo;
      limbs_[limb + 1] += mid;
      limbs_[limb + 2] += hi;
    }
    if (++terms_ == (std::uint64_t{1} << 30)) normalise();
  }

  void add(const ExactSum& o) {
    for (int i = 0; i < kLimbs; ++i) limbs_[i] += o.limbs_[i];
    special_ += o.special_;
    terms_ += o.terms_ + 1;
    normalise();
  }

  // Carries so that every limb but the last is in [0, 2^32): the one representation of the sum.
  void normalise() {
    for (int i = 0; i + 1 < kLimbs; ++i) {
      const std::int64_t carry = limbs_[i] >> 32;  // floor division (arithmetic shift)
      limbs_[i] -= carry * (std::int64_t{1} << 32);
      limbs_[i + 1] += carry;
    }
    terms_ = 0;
  }

  double value() {
    normalise();
    if (special_ != 0.0 || std::isnan(special_)) return special_;
    // Sign and magnitude, then round the top 128 bits (ties cannot flip with the sticky bit).
    std::array<std::int64_t, kLimbs> m = limbs_;
    const bool negative = m[kLimbs - 1] < 0;
    if (negative) {
      std::int64_t borrow = 0;
      for (int i = 0; i < kLimbs; ++i) {
        std::int64_t v = -m[i] - borrow;
        borrow = 0;
        if (i + 1 < kLimbs && v < 0) {
          v += std::int64_t{1} << 32;
          borrow = 1;
        }
        m[i] = v;
      }
    }
    int top = kLimbs - 1;
    while (top >= 0 && m[top] == 0) --top;
    if (top < 0) return 0.0;
    // Three limbs (up to 96 bits) from the top, plus a sticky bit for anything below, into a
    // long double-free rounding: build the value in two doubles and add once.
    double hi = 0.0, lo = 0.0;
    const int first = std::max(0, top - 2);
    std::uint64_t sticky = 0;
    for (int i = 0; i < first; ++i) sticky |= static_cast<std::uint64_t>(m[i]);
    U128 acc = 0;
    for (int i = top; i >= first; --i) acc = (acc << 32) | static_cast<std::uint64_t>(m[i]);
    acc = (acc << 1) | (sticky != 0 ? 1u : 0u);  // sticky below the last limb
    const int scale = first * 32 - kBias - 1;
    // acc < 2^97: split into two doubles exactly representable parts and sum once.
    const auto upper = static_cast<std::uint64_t>(acc >> 48);
    const auto lower = static_cast<std::uint64_t>(acc & ((std::uint64_t{1} << 48) - 1));
    hi = std::ldexp(static_cast<double>(upper), scale + 48);
    lo = std::ldexp(static_cast<double>(lower), scale);
    const double r = hi + lo;
    return negative ? -r : r;
  }

  std::array<std::int64_t, kLimbs>& limbs() { return limbs_; }
  double& special() { return special_; }

 private:
  std::array<std::int64_t, kLimbs> limbs_{};
  double special_ = 0.0;
  std::uint64_t terms_ = 0;
};

}  // namespace shatter::parallel
