#pragma once
// Time series of global quantities (energies, time step, momentum, failure ratio), one CSV row
// per sample, units in the header.

#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "shatter/core/energy.hpp"
#include "shatter/core/particles.hpp"
#include "shatter/parallel/exact_sum.hpp"

namespace shatter::io {

struct TimeSeriesRow {
  std::uint64_t step = 0;
  double time = 0.0;  // s
  double dt = 0.0;    // s
  EnergyBudget energy;
  Eigen::Vector3d momentum = Eigen::Vector3d::Zero();  // kg m/s
  double failure_ratio = 0.0;  // fraction of damage-carrying points with D >= threshold
  // Mass-weighted mean porosity 1 - 1/alpha of the porous points (issue 29): written only by a
  // writer made with porous = true (a scene with a porous material), as `mean_porosity`.
  double mean_porosity = 0.0;
  // The compaction work of the porous points, sum m q_c over the compaction_heat column (J;
  // issue 29): the part of internal_J spent closing pores. Written with mean_porosity, as
  // `compaction_J`.
  double compaction_work = 0.0;
  // The momentum enhancement (issue 32, include/shatter/fracture/beta.hpp): written only by a
  // writer made with beta = true (a scene with a [beta] table), as ejecta_mass_kg,
  // ejecta_momentum_kg_m_per_s, impactor_momentum_kg_m_per_s, beta, beta_target, beta_launch.
  double ejecta_mass = 0.0;        // kg
  double ejecta_momentum = 0.0;    // kg m/s, against the impact direction
  double impactor_momentum = 0.0;  // kg m/s
  double beta = 1.0;
  double beta_target = 0.0;
  double beta_launch = 1.0;  // counted at launch (shatter/fracture/ejecta_launch.hpp)
  double wall = 0.0;         // s since the run (or resume) started
};

// The CSV header line (without newline). With porous = true it has `mean_porosity` and
// `compaction_J` before `wall_s`; with beta = true the six beta columns (TimeSeriesRow) come before
// `wall_s` too.
std::string timeseries_header(bool porous = false, bool beta = false);

// How a resumed run takes over the time series of the run it continues.
struct ResumeRows {
  // The step of the last row the checkpoint covers: the row an uninterrupted run writes last at
  // or before the checkpoint's step (a multiple of timeseries_every; the checkpoint's own step
  // only at the end of a run). Later rows, such as the row a stop signal writes, go.
  std::uint64_t through_step = 0;
  // A file whose rows end before `through_step` (deleted, emptied or truncated): false throws
  // TimeSeriesGap; true keeps what there is (starting the file again if need be) and appends,
  // leaving the gap (note() says so).
  bool accept_gap = false;
};

// The time series lost rows the checkpoint covers.
struct TimeSeriesGap : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class TimeSeriesWriter {
 public:
  // Starts a new file.
  // porous: the scene has a porous material (ParticleStore::has(Field::distension)); the rows
  // then carry mean_porosity.
  // beta: the scene has a [beta] table; the rows then carry the beta columns.
  explicit TimeSeriesWriter(const std::filesystem::path& file, bool porous = false,
                            bool beta = false);
  // Resumes: keeps the complete rows of an existing file up to and including
  // `resume.through_step` and cuts the file after them (rows written after the checkpoint by a
  // run that then died, or a row torn by the crash, are dropped; the resumed run writes them
  // again), then appends.
  TimeSeriesWriter(const std::filesystem::path& file, const ResumeRows& resume, bool porous = false,
                   bool beta = false);

  // What a resume accepted (the rows missing), empty otherwise.
  const std::string& note() const { return note_; }

  void write(const TimeSeriesRow& row);
  // Throws when a write failed (disk full, ...).
  void flush();
  // flush() and fsync: the rows are on disk. Called before a checkpoint covering them commits.
  void sync();

 private:
  std::filesystem::path file_;
  bool porous_ = false;
  bool beta_ = false;
  std::string header_;
  std::ofstream out_;
  std::string note_;
};

// The porous points' sum m (1 - 1/alpha), their mass sum m and their compaction work sum m q_c
// (compaction_heat), exact (as momentum_sums): the points with a distension alpha >= 1, i.e.
// those of porous materials (the kernel sets alpha0 at initialise; the column is zero-filled for
// every other point). The ratio of the first two is the row's mean_porosity, the third its
// compaction_J; summed over the ranks first when distributed.
std::array<parallel::ExactSum, 3> porosity_sums(const ParticleStore& store);
// The ratio of porosity_sums, 0 without porous points.
double mean_porosity(const ParticleStore& store);
double mean_porosity(std::array<parallel::ExactSum, 3>& sums);

// Sum of m v over all particles (kg m/s).
// Sum of m v, exact (parallel::ExactSum): the same bits in any particle order, so a gathered
// or distributed store reports what one process does.
Eigen::Vector3d total_momentum(const ParticleStore& store);
std::array<parallel::ExactSum, 3> momentum_sums(const ParticleStore& store);
// Failed and counted points (failure_ratio's numerator and denominator), to add over ranks.
std::array<std::int64_t, 2> failure_counts(const ParticleStore& store, double threshold,
                                           const std::vector<bool>& counted);

// Fraction of the points of the flagged groups (`counted[g]` for group g) whose damage is at or
// above `threshold` (MPM paper Fig. 5: failed = D >= 0.9). 0 when no group is flagged or the
// store has no damage column.
double failure_ratio(const ParticleStore& store, double threshold,
                     const std::vector<bool>& counted);

// The same, weighted by mass: the failure ratio of the axisymmetric mode, where a point is a ring
// whose mass grows with its radius, so a count of points would weigh the axis' rings as much as
// the outer ones.
double failed_mass_fraction(const ParticleStore& store, double threshold,
                            const std::vector<bool>& counted);

}  // namespace shatter::io
