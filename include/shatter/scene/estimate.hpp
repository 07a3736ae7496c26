#pragma once
// What a scene will cost before any particle exists (`shatter check`, and `shatter run`'s guard
// against a scene larger than the machine): points per body, memory, time step, steps and run
// time.

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "shatter/scene/scene.hpp"

namespace shatter::scene {

struct BodyEstimate {
  std::string name;
  double points = 0.0;  // exact when counted, else volume / spacing^3 (half model applied)
  bool counted = false;
};

struct RunEstimate {
  std::vector<BodyEstimate> bodies;
  double points = 0.0;
  std::size_t columns = 0;        // particle columns the solver registers (8 bytes each)
  double bytes_per_point = 0.0;   // peak resident bytes per point, see estimate.cpp
  double bytes = 0.0;             // peak resident memory of the run
  double dt_first = 0.0;          // s, the first stable step (Eq. 34)
  double steps = 0.0;             // end_time / dt_first: a lower bound (dt shrinks in shocks)
  double seconds_per_core = 0.0;  // steps x points / measured throughput of one core
};

// Points from each body's volume and spacing (no lattice pass, no allocation of points).
std::vector<BodyEstimate> estimate_points(const Scene& scene);

// Points counted on the lattice without storing them (count_lattice), plus the checks that
// fill_bodies makes (domain, overlaps) done on the fly; throws SceneError like fill_bodies.
std::vector<BodyEstimate> count_and_check_points(const Scene& scene);

// Memory, first step and run time for `bodies` (from either function above). The first step
// comes from constructing the scene's solver on one point per body (all points of a body start
// in the same state, so Eq. 34's maximum is the same), so it is the solver's own number.
RunEstimate estimate_run(const Scene& scene, std::vector<BodyEstimate> bodies);

// Memory this process may still take: the smaller of MemAvailable (/proc/meminfo) and the
// cgroup limit less current use, or the environment variable SHATTER_MEMORY_LIMIT (bytes) when
// set. None when nothing can be read (not Linux).
std::optional<double> available_memory();

// "1.5 GiB", "730 MiB": bytes in binary units, three significant figures.
std::string format_bytes(double bytes);

}  // namespace shatter::scene
