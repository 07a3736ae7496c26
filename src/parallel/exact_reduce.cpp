#include "parallel/exact_reduce.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace shatter::parallel {

void sum_over_ranks(const Comm& comm, std::span<ExactSum* const> sums) {
  // The message: every sum's limbs, then one flag per sum for a special value.
  constexpr std::size_t L = ExactSum::kLimbs;
  const std::size_t n = sums.size();
  std::vector<std::int64_t> limbs(n * L + n);
  for (std::size_t k = 0; k < n; ++k) {
    sums[k]->normalise();
    std::copy(sums[k]->limbs().begin(), sums[k]->limbs().end(), limbs.begin() + k * L);
    const double sp = sums[k]->special();
    limbs[n * L + k] = sp != 0.0 || std::isnan(sp) ? 1 : 0;
  }
  comm.sum(limbs);
  for (std::size_t k = 0; k < n; ++k) {
    const auto at = limbs.begin() + static_cast<std::ptrdiff_t>(k * L);
    std::copy(at, at + L, sums[k]->limbs().begin());
    sums[k]->special() = limbs[n * L + k] > 0 ? std::nan("") : 0.0;
  }
}

}  // namespace shatter::parallel
