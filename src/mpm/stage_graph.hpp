#pragma once
// The step as a oneTBB flow graph (DESIGN.md "The step"). Each stage declares what it reads and
// writes (particle fields plus engine resources such as the grid); an edge runs from an earlier
// stage to a later one whenever they touch the same data and at least one of them writes it
// (read-after-write, write-after-read, write-after-write). Stages with no such conflict, such as
// the energy sums and the time-step reduction, run concurrently; every stage is itself
// data-parallel. Building the graph from declarations means the step contains exactly the stages
// the scene needs and nothing runs out of order.

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <tbb/flow_graph.h>

#include "shatter/core/fields.hpp"
#include "shatter/mpm/simulation.hpp"

namespace shatter::mpm {

// Engine data that is not a particle column.
enum Resource : std::uint32_t {
  kBlocks = 1u << 0,        // block structure and particle lists (sort stage)
  kGrid = 1u << 1,          // node mass, momentum, force
  kDisplacement = 1u << 2,  // particle displacement over the step (G2P -> advance)
  kClock = 1u << 3,
  kBudget = 1u << 4,      // energy accounts
  kMechanical = 1u << 5,  // mechanical energy at t^n per particle (G2P -> energy), and the
                          // transferred kinetic energy's sum (G2P -> finish_step)
};

struct Access {
  FieldSet fields;
  std::uint32_t resources = 0;
  bool overlaps(const Access& o) const {
    return (fields.lo & o.fields.lo) != 0 || (fields.hi & o.fields.hi) != 0 ||
           (resources & o.resources) != 0;
  }
};

struct Stage {
  std::string name;
  Access reads;
  Access writes;
  std::function<void()> run;
};

class StageGraph {
 public:
  void add(Stage stage) { stages_.push_back(std::move(stage)); }
  // Creates the flow-graph nodes and the dependency edges; call once after all add()s.
  void build();
  // Runs every stage once, respecting dependencies; rethrows the first exception.
  void run();
  const std::vector<StageTiming>& timings() const { return timings_; }

 private:
  std::vector<Stage> stages_;
  std::vector<StageTiming> timings_;
  std::unique_ptr<tbb::flow::graph> graph_;
  std::vector<std::unique_ptr<tbb::flow::continue_node<tbb::flow::continue_msg>>> nodes_;
  std::vector<std::size_t> sources_;
  std::vector<std::exception_ptr> errors_;  // one slot per stage: no shared writes
  std::atomic<bool> failed_{false};
};

}  // namespace shatter::mpm
