#pragma once
// Exact sums over the ranks: each rank's parallel::ExactSum limbs added as integers, so the
// total has the same bits for any rank count and any order (docs/mpi.md, "Determinism").

#include <span>

#include "shatter/parallel/comm.hpp"
#include "shatter/parallel/exact_sum.hpp"

namespace shatter::parallel {

// Replaces every sum by its total over the ranks, all in one message. A sum holding an
// infinity or NaN on any rank becomes NaN everywhere.
void sum_over_ranks(const Comm& comm, std::span<ExactSum* const> sums);

}  // namespace shatter::parallel
