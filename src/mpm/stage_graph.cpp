#include "mpm/stage_graph.hpp"

#include <exception>

namespace shatter::mpm {

void StageGraph::build() {
  graph_ = std::make_unique<tbb::flow::graph>();
  nodes_.clear();
  sources_.clear();
  timings_.assign(stages_.size(), {});
  errors_.assign(stages_.size(), nullptr);
  for (std::size_t s = 0; s < stages_.size(); ++s) {
    timings_[s].name = stages_[s].name;
    nodes_.push_back(std::make_unique<tbb::flow::continue_node<tbb::flow::continue_msg>>(
        *graph_, [this, s](const tbb::flow::continue_msg&) {
          // A failed stage stops the stages after it from running on broken data.
          if (failed_.load(std::memory_order_acquire)) return;
          const auto t0 = std::chrono::steady_clock::now();
          try {
            stages_[s].run();
          } catch (...) {
            errors_[s] = std::current_exception();
            failed_.store(true, std::memory_order_release);
          }
          timings_[s].seconds +=
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        }));
  }
  for (std::size_t j = 0; j < stages_.size(); ++j) {
    bool has_parent = false;
    for (std::size_t i = 0; i < j; ++i) {
      const Stage& a = stages_[i];
      const Stage& b = stages_[j];
      if (a.writes.overlaps(b.reads) || a.writes.overlaps(b.writes) || a.reads.overlaps(b.writes)) {
        tbb::flow::make_edge(*nodes_[i], *nodes_[j]);
        has_parent = true;
      }
    }
    if (!has_parent) sources_.push_back(j);
  }
}

void StageGraph::run() {
  for (auto& e : errors_) e = nullptr;
  failed_.store(false);
  for (const std::size_t s : sources_) nodes_[s]->try_put(tbb::flow::continue_msg());
  graph_->wait_for_all();
  for (const auto& e : errors_) {
    if (e) std::rethrow_exception(e);
  }
}

}  // namespace shatter::mpm
