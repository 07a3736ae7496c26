#pragma once
// What a scene with a [beta] table adds to a run (issue 32): beta(t) and the ejecta in the time
// series' row, and the ejecta launch table RUN/ejecta_launch.csv (written with each checkpoint
// and at the end, read back on a resume). The run loop holds one and calls it at its rows.

#include <filesystem>
#include <functional>

#include "shatter/core/particles.hpp"
#include "shatter/fracture/beta.hpp"
#include "shatter/fracture/ejecta_launch.hpp"
#include "shatter/io/timeseries.hpp"
#include "shatter/parallel/comm.hpp"

namespace shatter::cli {

class BetaOutput {
 public:
  BetaOutput(const BetaSpec& spec, const std::filesystem::path& out);

  // Fills the row's beta columns from this rank's points (exact sums over the ranks: the same
  // bits on any rank count) and records new launches from every point (`all`: the gathered
  // store on several ranks, called on every rank). Collective on several ranks.
  void sample(io::TimeSeriesRow& r, double time, const ParticleStore& local,
              const std::function<const ParticleStore&()>& all, const parallel::Comm& comm);
  // The launch table, whole and atomically (rank 0 only).
  void write() const;
  // On a resume (rank 0): the launches up to `time`; false (after logging why) when the table
  // is missing or unreadable.
  bool resume(double time);

 private:
  // Warns when non-impactor points start above the control plane (not a flat target).
  void warn_if_above(const ParticleStore& store) const;

  BetaSpec spec_;
  std::filesystem::path file_;
  EjectaLaunches launches_;
};

}  // namespace shatter::cli
