// Step control at a sudden stiffening (docs/stability.md, observation 2): when the state a step
// leaves has a stable step (Eq. 34) shorter than the step taken by more than
// SolverConfig::retake_ratio, the step is taken again with the shorter dt, so no accepted step
// runs at an effective CFL above retake_ratio x cfl.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <memory>
#include <string>

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
    const IncrementViews inc = increments_of(P, ctx);
    for (std::size_t p = r.begin; p < r.end; ++p) {
      const std::size_t q = p - inc.begin;
      const double tr = inc.deps[0][q] + inc.deps[1][q] + inc.deps[2][q];
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

namespace {

// The stiffening material with model state: plastic_strain (a model column the step writes and
// reads back) sums the compression, scaled by eps_min, a per-particle constant no stage writes.
class StiffeningWithState final : public MaterialModel {
 public:
  std::string name() const override { return "stiffening with state"; }
  FieldSet fields() const override { return {Field::plastic_strain, Field::eps_min}; }
  double reference_density() const override { return 1000.0; }
  void initialise(ParticleStore& P, Range r) const override {
    Stiffening{}.initialise(P, r);
    for (std::size_t p = r.begin; p < r.end; ++p) {
      P.col(Field::eps_min)[p] = 1.0 + static_cast<double>(P.col(IField::id)[p] % 7);
    }
  }
  void update(ParticleStore& P, Range r, const ConstitutiveContext& ctx) const override {
    Stiffening{}.update(P, r, ctx);
    const IncrementViews inc = increments_of(P, ctx);
    for (std::size_t p = r.begin; p < r.end; ++p) {
      const std::size_t q = p - inc.begin;
      const double tr = inc.deps[0][q] + inc.deps[1][q] + inc.deps[2][q];
      P.col(Field::plastic_strain)[p] += P.col(Field::eps_min)[p] * std::abs(tr);
    }
  }
};

// Every column (double and integer), the groups, the clock and the energy accounts, bit for bit.
void expect_same_state(const Simulation& a, const Simulation& b, int step) {
  const ParticleStore& P = a.particles();
  const ParticleStore& Q = b.particles();
  ASSERT_EQ(P.size(), Q.size()) << "step " << step;
  ASSERT_EQ(P.groups().size(), Q.groups().size());
  for (std::size_t g = 0; g < P.groups().size(); ++g) {
    EXPECT_EQ(P.groups()[g].range.begin, Q.groups()[g].range.begin) << "step " << step;
    EXPECT_EQ(P.groups()[g].range.end, Q.groups()[g].range.end) << "step " << step;
  }
  const std::size_t bytes = P.size() * sizeof(double);
  for (std::size_t i = 0; i < kFieldCount; ++i) {
    const auto f = static_cast<Field>(i);
    ASSERT_EQ(P.has(f), Q.has(f));
    if (!P.has(f)) continue;
    EXPECT_EQ(std::memcmp(P.col(f).data(), Q.col(f).data(), bytes), 0)
        << name_of(f) << " differs after step " << step;
  }
  for (std::size_t i = 0; i < kIFieldCount; ++i) {
    const auto f = static_cast<IField>(i);
    ASSERT_EQ(P.has(f), Q.has(f));
    if (!P.has(f)) continue;
    EXPECT_EQ(std::memcmp(P.col(f).data(), Q.col(f).data(), bytes), 0)
        << name_of(f) << " differs after step " << step;
  }
  const Clock& c = a.clock();
  const Clock& d = b.clock();
  EXPECT_EQ(std::memcmp(&c.time, &d.time, sizeof(double)), 0) << "step " << step;
  EXPECT_EQ(std::memcmp(&c.dt, &d.dt, sizeof(double)), 0) << "step " << step;
  EXPECT_EQ(std::memcmp(&c.dt_prev, &d.dt_prev, sizeof(double)), 0) << "step " << step;
  EXPECT_EQ(c.step, d.step);
  const EnergyBudget& e = a.energy();
  const EnergyBudget& h = b.energy();
  for (const auto m : {&EnergyBudget::kinetic, &EnergyBudget::internal, &EnergyBudget::potential,
                       &EnergyBudget::outflow, &EnergyBudget::boundary_work}) {
    EXPECT_EQ(std::memcmp(&(e.*m), &(h.*m), sizeof(double)), 0) << "step " << step;
  }
  const double ia = a.internal_next(), ib = b.internal_next();
  EXPECT_EQ(std::memcmp(&ia, &ib, sizeof(double)), 0) << "step " << step;
}

}  // namespace

TEST(StepRetake, RetakeRestoresTheStateBitwise) {
  // The retake saves only the columns a step writes and undoes the attempt's re-order and
  // outflow removals (Simulation::step). Reference: the same scene with retakes off, retaken by
  // hand from a full copy of the store, clock and energy accounts (what the engine did before).
  // The blocks touch at t = 0, so the first step is retaken, and in that step the columns are
  // re-ordered (reorder_interval 1; the lattice order is not the block order) and a layer of
  // points 0.5 mm inside the -y outflow face leaves (at 50 m/s, also in the retaken step).
  // Tolerance: none (bitwise), on 1 and 2 threads.
  const auto scene = [](double retake_ratio, int threads) {
    ParticleStore s;
    test::add_box(s, 0, Vector3d(0.0, 0.0, 0.0), Vector3d(0.4, 0.2, 0.2), 0.05, 1000.0,
                  Vector3d(50.0, 0.0, 0.0), 0);
    test::add_box(s, 0, Vector3d(0.4, 0.0, 0.0), Vector3d(0.8, 0.2, 0.2), 0.05, 1000.0,
                  Vector3d(-50.0, 0.0, 0.0), 1);
    test::add_box(s, 0, Vector3d(0.0, -0.1245, 0.0), Vector3d(0.2, -0.0745, 0.1), 0.05, 1000.0,
                  Vector3d(0.0, -50.0, 0.0), 2);
    SolverConfig cfg;
    cfg.cell_size = 0.1;
    cfg.retake_ratio = retake_ratio;
    cfg.reorder_interval = 1;
    cfg.domain.lo.y() = -0.1;
    cfg.domain.faces[2] = BoundaryKind::outflow;
    return std::make_unique<Simulation>(
        cfg, std::move(s), std::vector<MaterialPtr>{std::make_shared<StiffeningWithState>()},
        threads);
  };
  for (const int threads : {1, 2}) {
    auto engine = scene(2.0, threads);
    auto by_hand = scene(0.0, 1);
    const std::size_t n0 = by_hand->particles().size();
    const std::vector<std::int64_t> ids0(by_hand->particles().col(IField::id).begin(),
                                         by_hand->particles().col(IField::id).end());
    std::uint64_t retaken = 0;
    for (int k = 0; k < 12; ++k) {
      const ParticleStore start = by_hand->particles();
      const Clock clock = by_hand->clock();
      const EnergyBudget energy = by_hand->energy();
      const double internal = by_hand->internal_next();
      for (int attempt = 0;; ++attempt) {
        const double taken = by_hand->clock().dt;
        by_hand->step();
        if (attempt == Simulation::kMaxRetakes || !(taken > 2.0 * by_hand->clock().dt)) break;
        Clock again = clock;
        again.dt = by_hand->clock().dt;
        by_hand->particles() = start;
        by_hand->restore(again, energy, internal);
        ++retaken;
      }
      if (k == 0) {
        // The premises: the first step was retaken, re-ordered the store and lost points.
        ASSERT_GT(retaken, 0u);
        ASSERT_LT(by_hand->particles().size(), n0);
        const auto ids = by_hand->particles().col(IField::id);
        ASSERT_FALSE(std::equal(ids.begin(), ids.end(), ids0.begin()));
      }
      engine->step();
      expect_same_state(*engine, *by_hand, k);
      if (HasFatalFailure()) return;
    }
    EXPECT_EQ(engine->retakes(), retaken) << threads << " threads";
  }
}

TEST(StepRetake, TheColumnCopyChecksWhatItCopies) {
  // The sort stage's finite check leaves the velocity, stress, density and energy to the retake's
  // column copy, which tests them as it copies (Journal::save_columns); without retakes the
  // check reads them itself. Either way a non-finite value written between two steps stops the
  // next step, naming the column and the particle (by id: the sort may re-order the store).
  // Positions and sound speed, which the copy does not hold, are checked before the copy.
  for (const double ratio : {2.0, 0.0}) {
    for (const Field f : {Field::sxy, Field::vz, Field::energy, Field::y, Field::soundspeed}) {
      ParticleStore s;
      test::add_box(s, 0, Vector3d(0.0, 0.0, 0.0), Vector3d(0.4, 0.2, 0.2), 0.05, 1000.0,
                    Vector3d(50.0, 0.0, 0.0));
      SolverConfig cfg;
      cfg.cell_size = 0.1;
      cfg.retake_ratio = ratio;
      Simulation sim(cfg, std::move(s), {std::make_shared<Stiffening>()}, 1);
      sim.step();
      sim.step();
      const std::size_t k = sim.particles().size() / 3;
      const std::int64_t id = sim.particles().col(IField::id)[k];
      sim.particles().col(f)[k] = std::numeric_limits<double>::quiet_NaN();
      std::string what;
      try {
        sim.step();
      } catch (const NumericalError& e) {
        what = e.what();
      }
      const std::string expected = fmt::format("non-finite {} = nan", name_of(f));
      EXPECT_NE(what.find(expected), std::string::npos) << what << " (ratio " << ratio << ")";
      EXPECT_NE(what.find(fmt::format("(id {})", id)), std::string::npos) << what;
      EXPECT_NE(what.find("at step 2,"), std::string::npos) << what;
    }
  }
}
