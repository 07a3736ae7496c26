// Step control at a sudden stiffening (docs/stability.md, observation 2): when the state a step
// leaves has a stable step (Eq. 34) shorter than the step taken by more than
// SolverConfig::retake_ratio, the step is taken again with the shorter dt, so no accepted step
// runs at an effective CFL above retake_ratio x cfl.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <memory>

#include "shatter/mpm/simulation.hpp"
#include "support/lattice.hpp"

using namespace shatter;
using Eigen::Vector3d;

namespace {

// A stress-free material whose sound speed jumps from c_low to c_high wherever it is being
// compressed: the signal speed of a shock front (shocked c plus the viscosity's), reduced to the
// one property step control must handle, a jump the state at t^n does not announce.
class Stiffening final : public MaterialModel {
 public:
  static constexpr double kLow = 100.0, kHigh = 2000.0;
  std::string name() const override { return "stiffening"; }
  double reference_density() const override { return 1000.0; }
  void initialise(ParticleStore& P, Range r) const override {
    for (std::size_t p = r.begin; p < r.end; ++p) P.col(Field::soundspeed)[p] = kLow;
  }
  void update(ParticleStore& P, Range r, const ConstitutiveContext& ctx) const override {
    for (std::size_t p = r.begin; p < r.end; ++p) {
      const double tr =
          P.col(Field::deps_xx)[p] + P.col(Field::deps_yy)[p] + P.col(Field::deps_zz)[p];
      // Compression rate above 1e-3 /s: far above the round-off of a translating body (~1e-12
      // /s), far below that of contact at 100 m/s on 0.1 m cells (~1e3 /s).
      P.col(Field::soundspeed)[p] = -tr / ctx.dt > 1e-3 ? kHigh : kLow;
    }
  }
};

struct Outcome {
  double worst_ratio = 0.0;  // max over accepted steps of dt taken / next stable dt
  std::uint64_t retakes = 0;
  std::vector<double> x;  // final positions
};

// Two blocks closing at 100 m/s across a gap of two cells.
Outcome collide(double retake_ratio, int threads) {
  ParticleStore s;
  test::add_box(s, 0, Vector3d(0.0, 0.0, 0.0), Vector3d(0.4, 0.2, 0.2), 0.05, 1000.0,
                Vector3d(50.0, 0.0, 0.0), 0);
  test::add_box(s, 0, Vector3d(0.6, 0.0, 0.0), Vector3d(1.0, 0.2, 0.2), 0.05, 1000.0,
                Vector3d(-50.0, 0.0, 0.0), 1);
  SolverConfig cfg;
  cfg.cell_size = 0.1;
  cfg.retake_ratio = retake_ratio;
  Simulation sim(cfg, std::move(s), {std::make_shared<Stiffening>()}, threads);
  Outcome r;
  for (int k = 0; k < 30; ++k) {
    const double t0 = sim.time();
    sim.step();
    r.worst_ratio = std::max(r.worst_ratio, (sim.time() - t0) / sim.clock().dt);
  }
  r.retakes = sim.retakes();
  const auto x = sim.particles().col(Field::x);
  r.x.assign(x.begin(), x.end());
  return r;
}

}  // namespace

TEST(StepRetake, NoAcceptedStepOutrunsTheSignalSpeedItCreates) {
  // Without retakes the contact step runs at (c_high + v) / (c_low + v) = 14 times its stable
  // step; with them no accepted step exceeds retake_ratio (2) times the next stable step.
  const Outcome off = collide(0.0, 1);
  EXPECT_GT(off.worst_ratio, 10.0);
  EXPECT_EQ(off.retakes, 0u);
  const Outcome on = collide(2.0, 1);
  EXPECT_GT(on.retakes, 0u);
  EXPECT_LE(on.worst_ratio, 2.0);
  // Bitwise the same on two threads (docs/architecture.md, "Determinism").
  const Outcome two = collide(2.0, 2);
  EXPECT_EQ(two.retakes, on.retakes);
  ASSERT_EQ(two.x.size(), on.x.size());
  EXPECT_EQ(std::memcmp(two.x.data(), on.x.data(), on.x.size() * sizeof(double)), 0);
}

TEST(StepRetake, SmoothMotionIsNeverRetaken) {
  ParticleStore s;
  test::add_box(s, 0, Vector3d(0.0, 0.0, 0.0), Vector3d(0.4, 0.2, 0.2), 0.05, 1000.0,
                Vector3d(50.0, 0.0, 0.0));
  SolverConfig cfg;
  cfg.cell_size = 0.1;
  Simulation sim(cfg, std::move(s), {std::make_shared<Stiffening>()}, 1);
  for (int k = 0; k < 30; ++k) sim.step();
  EXPECT_EQ(sim.retakes(), 0u);
}
