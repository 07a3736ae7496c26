#pragma once
// Checkpoints: everything needed to continue a run bit for bit — every registered particle
// column (real and integer), the material groups, the integrator clock, the energy accounts, the
// output schedule and the resolved scene text the run was started from. Written to a temporary
// file and renamed over the previous checkpoint, so a crash while writing never destroys it.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <string>
#include <string_view>

#include "shatter/core/energy.hpp"
#include "shatter/core/particles.hpp"
#include "shatter/mpm/simulation.hpp"

namespace shatter::io {

// Where the output schedule stands, so a resumed run writes the same files at the same times.
struct OutputCursor {
  std::uint64_t next_snapshot = 0;    // index of the next snapshot file
  double next_snapshot_time = 0.0;    // s
  double next_checkpoint_time = 0.0;  // s
};

struct RunState {
  Clock clock;
  EnergyBudget energy;
  // Simulation::internal_next() when written; NaN when read from a format-1 checkpoint (resume
  // then sums it from the particles).
  double internal_next = std::numeric_limits<double>::quiet_NaN();
  // dt of the run's first step (the progress guard's dt floor is relative to it); 0 = unknown.
  double dt_first = 0.0;
  OutputCursor cursor;
  std::string scene_text;  // the resolved scene (TOML) the run was started from
  std::string program_version;
};

struct Checkpoint {
  ParticleStore particles;
  RunState state;
};

// Called after each dataset is written (name given). Lets a caller report progress; an exception
// thrown from it abandons the write and leaves the previous checkpoint in place.
using CheckpointProgress = std::function<void(std::string_view dataset)>;

void write_checkpoint(const std::filesystem::path& file, const ParticleStore& store,
                      const RunState& state, const CheckpointProgress& progress = {});

// Integrity (format 2): every dataset carries a CRC-32 of its values and the root attribute
// "state_crc32" covers the clock, energy and output-schedule attributes. Throws
// std::runtime_error naming the file when it is missing, truncated or not a checkpoint, and the
// file and the dataset when a checksum does not match. Format-1 checkpoints (no checksums) are
// still read.
Checkpoint read_checkpoint(const std::filesystem::path& file);

// Copies every column of `saved` into `live`: row by row when both hold the same number of
// particles (the order of the saved store is kept, which the SPH solver's sums depend on), by
// particle id when `live` holds one MPI rank's share (docs/mpi.md). The Simulation
// constructor re-initialises the constitutive state of the particles it is given (stress without
// the artificial viscosity of the step that wrote it, sound speed, ...); a resumed run puts the
// checkpointed values back so it continues bit for bit.
void restore_columns(ParticleStore& live, const ParticleStore& saved);

}  // namespace shatter::io
