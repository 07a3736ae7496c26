#pragma once
// The MPM step's communication (docs/mpi.md), each exchange a named stage of the step list
// (src/mpm/step.cpp): particle migration before the sort, the halo exchange of the node sums
// after each scatter (P2G's, the remap's, each filter pass's). Built into the MPM library (they
// work on its grid), kept here so that all communication lives in src/parallel.

#include "mpm/stage_graph.hpp"
#include "parallel/ranks.hpp"

namespace shatter::mpm {
struct State;
}

namespace shatter::parallel {

// Before the first step, on every rank holding the whole scene: the first cut of the curve,
// and each rank keeps the particles of its piece (migrate.cpp).
template <class Shape>
void distribute(mpm::State& s);
// 0. particles move to the rank that owns their owner block (after last step's positions); the
// curve is recut first when the load is uneven.
template <class Shape>
mpm::Stage migrate_stage(mpm::State& s);

// The halo plan, rebuilt by the sort stage when the grid or the decomposition changed.
void build_halo_plan(mpm::State& s);
// Inside the colour loop of a scatter: the halo blocks' nodes of colour c zeroed before it,
// its partial sums kept apart after it (halo.cpp).
void halo_zero(mpm::State& s, int colour, NodeFields fields);
void halo_capture(mpm::State& s, int colour, NodeFields fields);
// After a scatter: the partial sums of halo blocks to their owner, which forms each node's sum
// in colour order as one process does, mirrors the planes, and sends the sums back.
void halo_reduce(mpm::State& s, NodeFields fields);
// 1b. the exchange of the force-carrying P2G, a stage of its own.
mpm::Stage halo_stage(mpm::State& s);
// The exchange of a momentum-only scatter (the remap's, each filter pass's), a stage of its own
// that follows `scatter` in the step: "halo_" and its name. It declares the scatter's access, so
// every other stage is ordered against it as against the scatter. A filter pass's exchange
// (filter_pass) runs only on the steps the filter runs (State::filtering).
mpm::Stage momentum_halo_stage(mpm::State& s, const mpm::Stage& scatter, bool filter_pass);

}  // namespace shatter::parallel
