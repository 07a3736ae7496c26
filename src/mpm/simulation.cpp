#include "shatter/mpm/simulation.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <numeric>
#include <unordered_map>
#include <utility>

#include <fmt/format.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

#include "mpm/boundaries.hpp"
#include "mpm/contact.hpp"
#include "mpm/driven.hpp"
#include "mpm/kernel_inputs.hpp"
#include "mpm/stage_graph.hpp"
#include "shatter/core/solver_inputs.hpp"
#include "shatter/grid/sparse_grid.hpp"
#include "shatter/parallel/decomposition.hpp"
#include "shatter/parallel/exact_sum.hpp"

namespace shatter {
namespace {

// Calls f.operator()<Shape>() with the shape-function type the scene chose, so that each stage
// is compiled for one shape and a shape switch is written once.
template <class F>
void with_shape(ShapeKind kind, F&& f) {
  switch (kind) {
    case ShapeKind::linear:
      f.template operator()<kernels::LinearShape>();
      break;
    case ShapeKind::ugimp:
      f.template operator()<kernels::GimpShape>();
      break;
    case ShapeKind::bspline2:
      f.template operator()<kernels::BSpline2Shape>();
      break;
  }
}

using mpm::Access;
using mpm::Resource;

// Grain sizes are fixed (never derived from the thread count) so that every reduction splits
// the same way, and sums come out bitwise identical with 1 or N threads.
constexpr std::size_t kParticleGrain = 2048;

// Energy sums are exact (parallel::ExactSum): the same bits whatever the order of the
// particles in the store, the thread count or the number of ranks that hold them.
template <class F>
parallel::ExactSum exact_sum(std::size_t n, F&& term) {
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, n, kParticleGrain), parallel::ExactSum{},
      [&](const tbb::blocked_range<std::size_t>& r, parallel::ExactSum acc) {
        for (std::size_t p = r.begin(); p < r.end(); ++p) acc.add(term(p));
        return acc;
      },
      [](parallel::ExactSum a, const parallel::ExactSum& b) {
        a.add(b);
        return a;
      });
}

// -|p_I|^2 / (2 m_I) of one block's nodes (v: mass, px, py, pz of the block), the node half of
// the unresolved kinetic energy (Simulation::Impl::unresolved_kinetic); empty nodes add nothing.
void add_node_unresolved(const double* const (&v)[4], parallel::ExactSum& acc) {
  for (int l = 0; l < SparseGrid::kBlockNodes; ++l) {
    const double M = v[0][l];
    if (!(M > 0.0)) continue;
    acc.add(-0.5 * (v[1][l] * v[1][l] + v[2][l] * v[2][l] + v[3][l] * v[3][l]) / M);
  }
}

// The same over the blocks b < blocks with counted(b), field f of block b at at(b, f).
template <class Counted, class At>
parallel::ExactSum node_unresolved(std::size_t blocks, Counted&& counted, At&& at) {
  return tbb::parallel_reduce(
      tbb::blocked_range<std::uint32_t>(0, static_cast<std::uint32_t>(blocks), 16),
      parallel::ExactSum{},
      [&](const tbb::blocked_range<std::uint32_t>& r, parallel::ExactSum acc) {
        for (std::uint32_t b = r.begin(); b < r.end(); ++b) {
          if (!counted(b)) continue;
          const double* const v[4] = {at(b, 0), at(b, 1), at(b, 2), at(b, 3)};
          add_node_unresolved(v, acc);
        }
        return acc;
      },
      [](parallel::ExactSum a, const parallel::ExactSum& b) {
        a.add(b);
        return a;
      });
}

SparseGrid::Coord decode_key(std::uint64_t k) {
  constexpr std::int64_t off = std::int64_t{1} << 20;
  constexpr std::uint64_t mask = (std::uint64_t{1} << 21) - 1;
  return {static_cast<std::int32_t>(static_cast<std::int64_t>((k >> 42) & mask) - off),
          static_cast<std::int32_t>(static_cast<std::int64_t>((k >> 21) & mask) - off),
          static_cast<std::int32_t>(static_cast<std::int64_t>(k & mask) - off)};
}

// Node arrays a halo exchange carries: the force-carrying P2G (step 1) or momentum only (the
// MUSL remap and the XPIC passes).
constexpr int kForceFields = 7;
constexpr int kMomentumFields = 3;
std::array<std::vector<double>*, kForceFields> node_fields(SparseGrid::Nodes& N) {
  return {&N.mass, &N.px, &N.py, &N.pz, &N.fx, &N.fy, &N.fz};
}

// Test hook (tests/mpi): SHATTER_FAULT_INJECT="nan:RANK:STEP" puts a NaN into one velocity of
// that rank at that step, "throw:RANK:STEP" throws there; never set in a real run.
struct Fault {
  int kind = 0;  // 0 none, 1 nan, 2 throw
  int rank = -1;
  std::uint64_t step = 0;
};
Fault read_fault() {
  Fault f;
  const char* env = std::getenv("SHATTER_FAULT_INJECT");
  if (env == nullptr) return f;
  const std::string v(env);
  const auto a = v.find(':'), b = v.rfind(':');
  if (a == std::string::npos || a == b) return f;
  const std::string kind = v.substr(0, a);
  f.kind = kind == "nan" ? 1 : kind == "throw" ? 2 : 0;
  f.rank = std::atoi(v.substr(a + 1, b - a - 1).c_str());
  f.step = std::strtoull(v.substr(b + 1).c_str(), nullptr, 10);
  return f;
}

double env_double(const char* name, double fallback) {
  const char* env = std::getenv(name);
  return env != nullptr ? std::atof(env) : fallback;
}

const FieldSet kEngineFields =
    kPosition | kVelocity | kStress | kStrainIncrement | kSpinIncrement |
    FieldSet{Field::mass,   Field::volume0,  Field::size0,     Field::rho,
             Field::energy, Field::pressure, Field::soundspeed};

// What the step retake (Simulation::step) need not save. Constant: no stage writes these
// columns (mass, reference volume and size of the material point, and its flaw population: the
// damage models read eps_min, eps_max, n_flaws and weibull_m and store them back unchanged), nor
// the integer columns (id, body, fragment). Step-local: each step writes them for every particle
// before any stage reads them: the strain and spin increments (the velocity-gradient stage, App.
// A.2 step 7, before the constitutive update reads them), and pressure and sound speed, which
// MaterialModel::update sets for step n+1 from the rest of the state (its contract; the
// time-step and energy stages read them after it). Every other registered column is saved, so
// a column added later is saved unless it is listed here.
constexpr FieldSet kStepConstant{Field::mass,    Field::volume0, Field::size0,    Field::eps_min,
                                 Field::eps_max, Field::n_flaws, Field::weibull_m};
constexpr FieldSet kStepLocal =
    kStrainIncrement | kSpinIncrement | FieldSet{Field::pressure, Field::soundspeed};

// Copies n values of `columns` columns in parallel chunks: copy(column, begin, end).
template <class Copy>
void copy_columns(std::size_t columns, std::size_t n, Copy&& copy) {
  constexpr std::size_t kGrain = 16384;  // 128 KiB of doubles
  const std::size_t chunks = (n + kGrain - 1) / kGrain;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, columns * chunks),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t k = r.begin(); k < r.end(); ++k) {
                        const std::size_t c = k / chunks, b = (k % chunks) * kGrain;
                        copy(c, b, std::min(b + kGrain, n));
                      }
                    });
}

// APIC's C_p columns in row-major order, as the transfer kernels index them.
template <class T>
void vgrad_columns(ParticleStore& P, T* (&out)[9]) {
  constexpr Field kOrder[9] = {Field::vgrad_xx, Field::vgrad_xy, Field::vgrad_xz,
                               Field::vgrad_yx, Field::vgrad_yy, Field::vgrad_yz,
                               Field::vgrad_zx, Field::vgrad_zy, Field::vgrad_zz};
  for (int k = 0; k < 9; ++k) out[k] = P.col(kOrder[k]).data();
}

// The particles of every owner block, block by block in parallel, in runs that share one
// neighbour list (one run per block, except where bodies meet: then one per body): the unit
// of work of the gathers, which copy the run's nodes into a window first. Each particle's
// result depends on its own stencil only, so the split does not change any value.
// Block b's particles in consecutive runs that share one neighbour list: run(particles, list).
template <class Run>
void for_each_list_run(const SparseGrid& grid, std::uint32_t b, Run&& run) {
  const auto owned = grid.owned(b);
  std::size_t i = 0;
  while (i < owned.size()) {
    const std::uint32_t list = grid.list_of(owned[i]);
    std::size_t j = i + 1;
    while (j < owned.size() && grid.list_of(owned[j]) == list) ++j;
    run(owned.subspan(i, j - i), list);
    i = j;
  }
}

template <class Scratch, class Body>
void for_each_run(const SparseGrid& grid, Body&& body) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, grid.shared_blocks(), 1),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      Scratch scratch;
                      for (std::size_t k = r.begin(); k < r.end(); ++k) {
                        const auto b = static_cast<std::uint32_t>(k);
                        for_each_list_run(grid, b, [&](auto run, std::uint32_t list) {
                          body(run, grid.coord(b), grid.list(list), scratch);
                        });
                      }
                    });
}

FieldSet all_fields() {
  FieldSet s;
  for (std::size_t i = 0; i < kFieldCount; ++i) s = s.with(static_cast<Field>(i));
  return s;
}

}  // namespace

struct Simulation::Impl {
  Simulation& sim;
  // The ranks (docs/mpi.md). With one rank nothing below the `dist` checks runs.
  const parallel::Comm& comm = parallel::world();
  const bool dist = parallel::world().distributed();
  parallel::Decomposition decomp;
  std::uint64_t decomp_version = 0, plan_version = ~std::uint64_t{0};
  std::uint64_t rebalances = 0;
  unsigned rebalance_every = 10;  // steps between load checks (SHATTER_MPI_REBALANCE_EVERY)
  double imbalance = 1.2;  // max/mean particles that triggers a recut (SHATTER_MPI_IMBALANCE)
  parallel::Traffic halo_traffic, migrate_traffic;
  Fault fault = read_fault();
  // Halo plan (rebuilt when the grid or the decomposition changes). Halo blocks: blocks another
  // rank owns (ghosts: their partial sums go to the owner, the final sums come back) and owned
  // blocks that owner blocks of other ranks may reach (their sums are formed from the partials
  // of every rank, colour by colour, as in one process).
  struct Halo {
    std::vector<std::uint32_t> blocks;  // local block index per halo block
    std::vector<int> owner;             // owner rank per halo block
    std::vector<std::int32_t> slot;     // per halo block x colour: slot of the local partial, or -1
    std::array<std::vector<std::uint32_t>, SparseGrid::kColours> by_colour;  // halo blocks
    std::vector<double> slots;                                               // slot x field x node
    std::vector<std::uint8_t> owned;     // per local block: this rank owns it (energy sums)
    std::vector<std::size_t> ghosts_to;  // per rank: ghost blocks sent there
  } halo;
  // Sums of the step, combined over ranks after the graph (finish_step).
  parallel::ExactSum kinetic_sum, potential_sum, internal_sum, carried_sum, carried_internal_sum,
      removed_sum;
  // Unresolved kinetic energy (issue 16, docs/outputs.md): sum_p m_p |v_p|^2/2 of the velocities
  // the step's P2G transferred, plus -sum_I |p_I|^2/(2 m_I) of its nodes, in one exact sum.
  parallel::ExactSum transferred_sum, unresolved_sum;
  double fastest = 0.0;
  std::string failure;  // a numerical failure of this rank in this step (distributed runs)
  std::size_t failure_particle = 0;
  SparseGrid grid;
  mpm::StageGraph graph;
  tbb::task_arena arena;
  std::vector<std::uint64_t> owner_keys;
  std::vector<std::uint32_t> order;
  AlignedVector<double> dx, dy, dz, kinetic, potential;
  // 1/2 m_p |v_p|^2 of the velocity each particle scattered in this step's P2G (v^{n-1/2}),
  // written by G2P; outflow does not drop the departed ones (their momentum is on the nodes).
  AlignedVector<double> kinetic_transferred;
  AlignedVector<double> bx, by, bz;  // body force per unit mass, when the scene has one
  // Each particle's stencil (weights, gradients, offsets), stored by the sort stage and read by
  // every transfer of the step (kernels::StencilCache).
  AlignedVector<double> stencil_w;
  std::vector<std::uint8_t> stencil_off;
  mpm::Boundaries boundaries;
  // Multi-velocity-field contact: set only when the scene asks for it and has two bodies or
  // more; otherwise the step is the single-field step, bitwise.
  std::unique_ptr<mpm::Contact> contact;
  std::unique_ptr<mpm::DrivenBodies> driven;  // prescribed-velocity bodies (set_driven)
  std::vector<double> step4_velocity;         // body-copy node velocities kept through the remap
  // XPIC (TransferKind::xpic): v^{n+1} kept aside while the grid momentum arrays hold the extra
  // passes, the running (S+ S)^{k-1} term, the filtered velocity V*_m + a dt handed to G2P, and
  // the interpolated velocities S V of one pass at the particles.
  std::vector<double> xpic_v[3], xpic_term[3], xpic_target[3];
  AlignedVector<double> xpic_w[3];
  // The step being taken applies the XPIC/FMPM filter (SolverConfig::filter_every); set by
  // Simulation::step from the step counter before the graph runs, the same on a retake.
  bool filtering = true;
  double dt_step = 0.0;        // dt^{n+1/2} of the step being taken
  double internal_next = 0.0;  // sum m E at t^{n+1}, reported with the next step
  double empty_mass = 0.0;     // nodes lighter than this are treated as empty
  // The state before the step being taken, to take it again (Simulation::step): the columns
  // the step changes, and a record of what the attempt under way did to the store's layout
  // (re-order, outflow, migration), which the restore undoes. Constant and step-local columns
  // (kStepConstant, kStepLocal) are not copied.
  struct Saved {
    std::vector<Field> fields;                // registered columns the step writes
    std::vector<AlignedVector<double>> cols;  // their values at t^n, in the order of `fields`
    std::vector<Group> groups;                // the groups at t^n
    Clock clock;
    EnergyBudget energy;
    double internal_next = 0.0;
    bool armed = false;     // the attempt under way may be retaken: record layout changes
    bool permuted = false;  // the sort stage re-ordered the store by `order`
    // Outflow removed the particles flagged here (over the store before the removal; empty:
    // none); their unsaved columns, in store order.
    std::vector<std::uint8_t> left;
    std::array<std::vector<double>, kFieldCount> left_rows;
    std::array<std::vector<std::int64_t>, kIFieldCount> left_irows;
    bool whole = false;   // migration moved particles; `store` is the whole store at t^n
    ParticleStore store;  // (the store migration replaced, moved here rather than freed)
    StageTiming timing{"retake_copy", 0.0};  // wall time of the saves and restores
  } saved;
  std::vector<StageTiming> timings;  // stage_timings(): the graph's and the retake's

  Impl(Simulation& s, int threads)
      : sim(s),
        arena(threads > 0 ? threads : tbb::task_arena::automatic),
        boundaries(s.config_.domain, s.config_.cell_size) {}

  double inv_h() const { return 1.0 / sim.config_.cell_size; }
  kernels::StencilCache stencils(kernels::StencilCache::Mode mode) {
    return {stencil_w.data(), stencil_off.data(), mode};
  }

  template <class Shape>
  void build_stages();
  template <class Shape>
  void sort();
  template <class Shape>
  void p2g(bool with_force, double* const* velocity = nullptr);
  template <class Shape>
  void p2g_bodies(const kernels::P2GParticles& in, bool with_force);
  void grid_update();
  void unresolved_kinetic();
  double filtered_share() const;
  bool filters_step(std::uint64_t step) const;
  template <class Shape, class Update>
  void series_passes(int terms, Update&& update);
  template <class Shape>
  void xpic();
  template <class Shape>
  void fmpm();
  template <class Shape>
  void g2p();
  template <class Shape>
  void remap();
  template <class Shape>
  void velocity_gradient();
  void constitutive();
  void advance_positions();
  void outflow();
  void energy();
  void time_step();
  double stable_dt();
  double fastest_local() const;
  void check_finite() const;
  // Distributed runs (docs/mpi.md)
  template <class Shape>
  void compute_keys();
  template <class Shape>
  void distribute();
  template <class Shape>
  void migrate();
  void rebalance_if_needed();
  void build_halo_plan();
  void halo_zero(int colour, int fields);
  void halo_capture(int colour, int fields);
  void halo_reduce(int fields);
  bool decomp_planes_empty() const;
  void finish_step();
  double global(parallel::ExactSum s) const;
  // The step retake (Simulation::step)
  bool saves(Field f) const;
  void save_step();
  void restore_step();
  void keep_leaving(std::span<const std::uint8_t> leaving);
  void undo_outflow();
};

Simulation::Simulation(SolverConfig config, ParticleStore particles,
                       std::vector<MaterialPtr> materials, int threads)
    : config_(std::move(config)),
      particles_(std::move(particles)),
      materials_(std::move(materials)),
      threads_(threads) {
  if (!(config_.cell_size > 0.0) || !std::isfinite(config_.cell_size)) {
    throw std::invalid_argument(
        fmt::format("solver: cell_size must be > 0, got {}", config_.cell_size));
  }
  if (!(config_.cfl > 0.0 && config_.cfl <= 1.0)) {
    throw std::invalid_argument(
        fmt::format("solver: cfl must be in (0, 1] (Eq. 34), got {}", config_.cfl));
  }
  check_solver_inputs(
      particles_, materials_,
      {Field::x, Field::y, Field::z, Field::vx, Field::vy, Field::vz, Field::mass, Field::rho});
  if (config_.transfer == TransferKind::apic && config_.shape == ShapeKind::linear) {
    // C_p = sum v_I grad N_I^T jumps when a point crosses a cell face with linear shapes; the
    // colliding-sphere test diverges within 50 steps. Jiang et al. (2015) use smooth kernels.
    throw std::invalid_argument(
        "solver: transfer 'apic' needs a smooth shape function (ugimp or bspline2), not 'linear'");
  }
  if (!(config_.pic_fraction >= 0.0 && config_.pic_fraction <= 1.0)) {
    throw std::invalid_argument(
        fmt::format("solver: pic_fraction must be in [0, 1], got {}", config_.pic_fraction));
  }
  if (config_.pic_fraction != 0.0 && config_.transfer != TransferKind::flip) {
    throw std::invalid_argument(fmt::format(
        "solver: pic_fraction applies only to transfer 'flip' (the FLIP/PIC blend), not '{}'",
        name_of(config_.transfer)));
  }
  // Orders past ~40 are unstable (Hammerquist & Nairn 2017; each order is one more
  // grid-particle-grid pass), and the binomial weights C(m, k) lose precision.
  constexpr int kMaxXpicOrder = 32;
  if (config_.transfer == TransferKind::xpic &&
      (config_.xpic_order < 1 || config_.xpic_order > kMaxXpicOrder)) {
    throw std::invalid_argument(fmt::format("solver: xpic_order must be in [1, {}], got {}",
                                            kMaxXpicOrder, config_.xpic_order));
  }
  // FMPM(k): the same passes as XPIC, so the same bound; Nairn (2026, arXiv 2604.07307) finds
  // high orders need smaller time steps, so large k is for study, not production.
  constexpr int kMaxFmpmOrder = 32;
  if (config_.transfer == TransferKind::fmpm &&
      (config_.fmpm_order < 1 || config_.fmpm_order > kMaxFmpmOrder)) {
    throw std::invalid_argument(fmt::format("solver: fmpm_order must be in [1, {}], got {}",
                                            kMaxFmpmOrder, config_.fmpm_order));
  }
  if (config_.filter_every < 1) {
    throw std::invalid_argument(
        fmt::format("solver: filter_every must be >= 1, got {}", config_.filter_every));
  }
  if (config_.filter_every != 1 && config_.transfer != TransferKind::xpic &&
      config_.transfer != TransferKind::fmpm) {
    // APIC's C_p and the blend's fraction act on every step; a FLIP step would drop C_p.
    throw std::invalid_argument(
        fmt::format("solver: filter_every applies only to transfer 'xpic' or 'fmpm', not '{}'",
                    name_of(config_.transfer)));
  }
  if (particles_.has(Field::size0)) {
    // A zero size would make the uGIMP weights 0/0; such particles get the cubic-lattice size.
    auto s = particles_.col(Field::size0);
    for (std::size_t p = 0; p < particles_.size(); ++p) {
      if (!(s[p] > 0.0))
        s[p] = std::cbrt(particles_.col(Field::mass)[p] / particles_.col(Field::rho)[p]);
    }
  }
  if (!particles_.has(Field::size0)) {
    // uGIMP needs the undeformed particle size; without one, take the spacing of a cubic lattice
    // of the particle's volume.
    particles_.require(Field::size0);
    auto s = particles_.col(Field::size0);
    auto m = particles_.col(Field::mass);
    auto r = particles_.col(Field::rho);
    for (std::size_t p = 0; p < particles_.size(); ++p) s[p] = std::cbrt(m[p] / r[p]);
  }
  particles_.require(kEngineFields);
  // C_p starts at zero: the scene gives velocities, not their gradients.
  if (config_.transfer == TransferKind::apic) particles_.require(kVelocityGradient);
  particles_.require(IField::id);
  for (const auto& m : materials_) particles_.require(m->fields());
  for (const Group& g : particles_.groups()) {
    materials_[static_cast<std::size_t>(g.material)]->initialise(particles_, g.range);
  }

  impl_ = std::make_unique<Impl>(*this, threads);
  {
    const ContactConfig& cc = config_.contact;
    if (!(cc.friction >= 0.0 && std::isfinite(cc.friction))) {
      throw std::invalid_argument(
          fmt::format("solver: contact friction must be finite and >= 0, got {}", cc.friction));
    }
    for (const ContactPair& pr : cc.pairs) {
      constexpr std::int64_t kMaxId = std::int64_t{1} << 32;  // mpm::Contact's pair key
      if (!(pr.friction >= 0.0 && std::isfinite(pr.friction)) || pr.a < 0 || pr.b < 0 ||
          pr.a >= kMaxId || pr.b >= kMaxId || pr.a == pr.b) {
        throw std::invalid_argument(fmt::format(
            "solver: contact pair ({}, {}) needs two different body ids in [0, 2^32) and a "
            "finite friction >= 0, got {}",
            pr.a, pr.b, pr.friction));
      }
    }
    if (cc.kind == ContactKind::multi_field && particles_.has(IField::body)) {
      const auto body = particles_.col(IField::body);
      const auto [lo, hi] = std::minmax_element(body.begin(), body.end());
      if (*lo < 0) {
        throw std::invalid_argument(
            fmt::format("particle {} has body id {} (multi-field contact needs ids >= 0)",
                        lo - body.begin(), *lo));
      }
      if (*lo != *hi) impl_->contact = std::make_unique<mpm::Contact>(cc);
    }
  }
  const auto masses = particles_.col(Field::mass);
  impl_->empty_mass = 1e-12 * *std::min_element(masses.begin(), masses.end());
  if (impl_->dist) {
    // Combinations the decomposition does not carry yet (docs/mpi.md, "Gaps"): refused here,
    // on every rank alike, rather than run with results that depend on the rank count.
    if (impl_->contact) {
      throw std::invalid_argument(
          "solver: contact 'multi_field' is not supported on more than one MPI rank yet (body "
          "copies would need the meetings of every rank); run it on one rank");
    }
    // Symmetry and fixed faces: ghost nodes and their partners get one owner, who mirrors them
    // (halo_reduce).
    std::vector<std::pair<int, std::int64_t>> planes;
    for (const auto& pl : impl_->boundaries.planes()) {
      if (pl.kind == BoundaryKind::symmetry || pl.kind == BoundaryKind::fixed) {
        planes.emplace_back(pl.axis, pl.index);
      }
    }
    impl_->decomp.set_planes(std::move(planes));
    impl_->rebalance_every =
        static_cast<unsigned>(std::max(1.0, env_double("SHATTER_MPI_REBALANCE_EVERY", 10.0)));
    impl_->imbalance = env_double("SHATTER_MPI_IMBALANCE", 1.2);
  }

  impl_->arena.execute([&] {
    with_shape(config_.shape, [&]<class Shape>() { impl_->build_stages<Shape>(); });
    impl_->check_finite();
    if (impl_->dist) {
      // Every rank built the whole scene (the same bits: flaws are drawn per particle id);
      // each keeps the particles of its piece of the curve.
      with_shape(config_.shape, [&]<class Shape>() { impl_->distribute<Shape>(); });
    }
    // Initial energy: v^0 is both the "synchronised" and the stored velocity at t = 0.
    const auto& P = particles_;
    const auto m = P.col(Field::mass), e = P.col(Field::energy);
    const auto vx = P.col(Field::vx), vy = P.col(Field::vy), vz = P.col(Field::vz);
    const auto x = P.col(Field::x), y = P.col(Field::y), z = P.col(Field::z);
    const Vec3 g = config_.gravity;
    energy_.kinetic = impl_->global(exact_sum(P.size(), [&](std::size_t p) {
      return 0.5 * m[p] * (vx[p] * vx[p] + vy[p] * vy[p] + vz[p] * vz[p]);
    }));
    energy_.internal =
        impl_->global(exact_sum(P.size(), [&](std::size_t p) { return m[p] * e[p]; }));
    energy_.potential = impl_->global(exact_sum(P.size(), [&](std::size_t p) {
      return -m[p] * (g.x() * x[p] + g.y() * y[p] + g.z() * z[p]);
    }));
    energy_.initial = energy_.total();
    energy_.scale = std::abs(energy_.kinetic) + std::abs(energy_.internal);
    impl_->internal_next = energy_.internal;
    clock_.dt = impl_->stable_dt();
  });
}

Simulation::~Simulation() = default;

std::size_t Simulation::active_blocks() const {
  return impl_->grid.blocks();
}
std::size_t Simulation::grid_bytes() const {
  return impl_->grid.bytes();
}
double Simulation::grid_mass() const {
  const auto& m = impl_->grid.nodes().mass;
  return std::accumulate(m.begin(), m.end(), 0.0);
}
const std::vector<StageTiming>& Simulation::stage_timings() const {
  // The graph's stages, then the retake's copies, which step() makes outside the graph.
  std::vector<StageTiming>& out = impl_->timings;
  out = impl_->graph.timings();
  out.push_back(impl_->saved.timing);
  return out;
}
parallel::Traffic Simulation::halo_traffic() const {
  return impl_->halo_traffic;
}
parallel::Traffic Simulation::migrate_traffic() const {
  return impl_->migrate_traffic;
}
std::uint64_t Simulation::rebalances() const {
  return impl_->rebalances;
}

void Simulation::set_driven(const std::vector<std::int32_t>& bodies) {
  if (bodies.empty()) {
    impl_->driven.reset();
    return;
  }
  if (impl_->dist) {
    throw std::invalid_argument(
        "driven bodies (body.NAME.driven) run on one MPI rank only: the prescribed nodes of a "
        "body that several ranks share are not exchanged");
  }
  impl_->driven = std::make_unique<mpm::DrivenBodies>(particles_, bodies);
}

void Simulation::restore(const Clock& clock, const EnergyBudget& energy) {
  clock_ = clock;
  energy_ = energy;
  impl_->internal_next = impl_->global(exact_sum(particles_.size(), [&](std::size_t p) {
    return particles_.col(Field::mass)[p] * particles_.col(Field::energy)[p];
  }));
}

void Simulation::restore(const Clock& clock, const EnergyBudget& energy, double internal_next) {
  clock_ = clock;
  energy_ = energy;
  impl_->internal_next = internal_next;
}

double Simulation::internal_next() const {
  return impl_->internal_next;
}

void Simulation::step() {
  // Eq. 34 sets dt from the state at t^n; a step in which the signal speed jumps (first contact
  // at hypervelocity: the shocked sound speed plus the viscosity's signal speed) runs at an
  // effective CFL of cfl x dt / (the stable step of the state it leaves) — 1.3 at the first
  // contact of the 15 km/s impact, with a +1.8 % energy error made in that one step. The jump
  // cannot be predicted from particle data at t^n (before contact nothing is compressed), so
  // when the stable step of the state left is shorter than the step taken by more than
  // retake_ratio, the step is taken again with that shorter step. The decision compares two
  // exact maxima (Eq. 34), so it is the same on any thread count. Cost: one copy per step of the
  // columns the step writes (docs/stability.md, docs/performance.md).
  // What is saved is what the step writes and reads first (positions, velocities, density,
  // stress, energy, model state; kStepConstant and kStepLocal name what is not), and the
  // restore undoes the attempt's re-order, outflow removals and migration, so a retaken step
  // starts from the bits it started from before (StepRetake.RetakeRestoresTheStateBitwise).
  Impl::Saved& sv = impl_->saved;
  const auto timed = [&](auto&& f) {
    const auto t0 = std::chrono::steady_clock::now();
    impl_->arena.execute(f);
    sv.timing.seconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  const bool may_retake = config_.retake_ratio > 0.0;
  if (may_retake) timed([&] { impl_->save_step(); });
  for (int attempt = 0;; ++attempt) {
    sv.armed = may_retake;
    sv.permuted = sv.whole = false;
    sv.left.clear();
    impl_->dt_step = clock_.dt;
    impl_->filtering = impl_->filters_step(clock_.step);
    impl_->arena.execute([&] { impl_->graph.run(); });
    impl_->finish_step();
    if (!may_retake || attempt == kMaxRetakes ||
        !(impl_->dt_step > config_.retake_ratio * clock_.dt)) {
      break;
    }
    const double shorter = clock_.dt;
    timed([&] { impl_->restore_step(); });
    clock_.dt = shorter;
    ++retakes_;
  }
  sv.armed = false;
  sv.store = ParticleStore{};  // a store migration replaced is freed, as it was before
}

bool Simulation::Impl::saves(Field f) const {
  return sim.particles_.has(f) && !kStepConstant.has(f) && !kStepLocal.has(f);
}

void Simulation::Impl::save_step() {
  const ParticleStore& P = sim.particles_;
  const std::size_t n = P.size();
  saved.fields.clear();
  for (std::size_t i = 0; i < kFieldCount; ++i) {
    if (saves(static_cast<Field>(i))) saved.fields.push_back(static_cast<Field>(i));
  }
  saved.cols.resize(saved.fields.size());
  for (auto& c : saved.cols) c.resize(n);  // reuses the buffers of the last step
  copy_columns(saved.fields.size(), n, [&](std::size_t c, std::size_t b, std::size_t e) {
    const double* src = P.col(saved.fields[c]).data();
    std::copy(src + b, src + e, saved.cols[c].data() + b);
  });
  saved.groups = P.groups();
  saved.clock = sim.clock_;
  saved.energy = sim.energy_;
  saved.internal_next = internal_next;
}

void Simulation::Impl::restore_step() {
  ParticleStore& P = sim.particles_;
  if (saved.whole) {
    P = saved.store;  // taken before migration moved anything: the store at t^n
  } else {
    // Undo in the reverse order of the step: the outflow removal, then the re-order.
    if (!saved.left.empty()) undo_outflow();
    if (saved.permuted) {
      std::vector<std::uint32_t> inverse(order.size());
      for (std::size_t k = 0; k < order.size(); ++k)
        inverse[order[k]] = static_cast<std::uint32_t>(k);
      P.permute(inverse);
    }
    copy_columns(saved.fields.size(), P.size(), [&](std::size_t c, std::size_t b, std::size_t e) {
      const double* src = saved.cols[c].data();
      std::copy(src + b, src + e, P.col(saved.fields[c]).data() + b);
    });
  }
  sim.clock_ = saved.clock;
  sim.energy_ = saved.energy;
  internal_next = saved.internal_next;
}

// Outflow is about to remove the flagged particles: keep their unsaved columns.
void Simulation::Impl::keep_leaving(std::span<const std::uint8_t> leaving) {
  if (!saved.armed || saved.whole) return;
  const ParticleStore& P = sim.particles_;
  saved.left.assign(leaving.begin(), leaving.end());
  for (std::size_t i = 0; i < kFieldCount; ++i) {
    const auto f = static_cast<Field>(i);
    saved.left_rows[i].clear();
    if (!P.has(f) || saves(f)) continue;
    const auto c = P.col(f);
    for (std::size_t p = 0; p < leaving.size(); ++p) {
      if (leaving[p]) saved.left_rows[i].push_back(c[p]);
    }
  }
  for (std::size_t i = 0; i < kIFieldCount; ++i) {
    const auto f = static_cast<IField>(i);
    saved.left_irows[i].clear();
    if (!P.has(f)) continue;
    const auto c = P.col(f);
    for (std::size_t p = 0; p < leaving.size(); ++p) {
      if (leaving[p]) saved.left_irows[i].push_back(c[p]);
    }
  }
}

// The store as it was before outflow's removal (the columns restore_step copies back are left
// zero here): the departed particles' rows merged back in their places.
void Simulation::Impl::undo_outflow() {
  ParticleStore& P = sim.particles_;
  const std::vector<std::uint8_t>& left = saved.left;
  ParticleStore B;
  B.require(P.registered());
  for (std::size_t i = 0; i < kIFieldCount; ++i) {
    if (P.has(static_cast<IField>(i))) B.require(static_cast<IField>(i));
  }
  for (const Group& g : saved.groups) B.add_group(g.material, g.range.size());
  const auto merge = [&](auto dst, auto src, const auto& rows) {
    std::size_t k = 0, j = 0;
    for (std::size_t p = 0; p < left.size(); ++p) dst[p] = left[p] ? rows[j++] : src[k++];
  };
  for (std::size_t i = 0; i < kFieldCount; ++i) {
    const auto f = static_cast<Field>(i);
    if (P.has(f) && !saves(f)) merge(B.col(f), std::as_const(P).col(f), saved.left_rows[i]);
  }
  for (std::size_t i = 0; i < kIFieldCount; ++i) {
    const auto f = static_cast<IField>(i);
    if (P.has(f)) merge(B.col(f), std::as_const(P).col(f), saved.left_irows[i]);
  }
  P = std::move(B);
}

void Simulation::advance_to(double t) {
  // Steps shorter than this fraction of the stable step are merged into the previous one rather
  // than taken alone, so output times do not produce sliver steps.
  constexpr double kSliver = 1e-3;
  while (clock_.time < t) {
    const double remaining = t - clock_.time;
    if (remaining <= kSliver * clock_.dt) {
      clock_.time = t;
      break;
    }
    if (clock_.dt > remaining) clock_.dt = remaining;
    step();
  }
}

// The MUSL step of App. A.2, one stage per line. Each stage's declaration lists the data it
// reads and writes; the graph orders the stages from those declarations.
template <class Shape>
void Simulation::Impl::build_stages() {
  const FieldSet all = all_fields();
  const FieldSet models = [&] {
    FieldSet s;
    for (const auto& m : sim.materials_) s = s | m->fields();
    return s;
  }();
  const FieldSet geometry = kPosition | FieldSet{Field::size0};
  using R = Resource;
  const bool apic = sim.config_.transfer == TransferKind::apic;
  const FieldSet affine = apic ? kVelocityGradient : FieldSet{};

  // 0. particles move to the rank that owns their owner block (after last step's positions);
  // the curve is recut here when the load is uneven (docs/mpi.md)
  if (dist) {
    graph.add({"migrate", {geometry, R::kClock}, {all, R::kBlocks}, [this] { migrate<Shape>(); }});
  }
  // 1. sort particles by grid block (and re-order the columns every few steps)
  graph.add({"sort", {geometry, R::kClock}, {all, R::kBlocks}, [this] { sort<Shape>(); }});
  // 1, 3. scatter mass, momentum and internal force to the grid (Eqs. 29, 32, 33)
  graph.add(
      {"p2g",
       {geometry | kVelocity | kStress | affine | FieldSet{Field::mass, Field::rho}, R::kBlocks},
       {{}, R::kGrid},
       [this] { p2g<Shape>(true); }});
  // 1b. partial node sums of blocks several ranks reach go to the owner, which adds them in
  // colour order; final sums come back (docs/mpi.md)
  if (dist) {
    graph.add({"halo", {{}, R::kBlocks}, {{}, R::kGrid}, [this] { halo_reduce(kForceFields); }});
  }
  // 2, 3, 4. boundary conditions and the momentum update on the grid (Eq. 27)
  graph.add({"grid_update", {{}, R::kClock | R::kBlocks}, {{}, R::kGrid | R::kBudget}, [this] {
               grid_update();
             }});
  // 5a. XPIC(m): the m - 1 extra grid-particle-grid passes that build V*_m (TransferKind::xpic)
  if (sim.config_.transfer == TransferKind::xpic && sim.config_.xpic_order > 1) {
    graph.add({"xpic",
               {geometry | FieldSet{Field::mass}, R::kBlocks | R::kClock},
               {{}, R::kGrid},
               [this] {
                 if (filtering) xpic<Shape>();
               }});
  }
  // 5a. FMPM(k): the k - 1 extra passes that build v_F (TransferKind::fmpm)
  if (sim.config_.transfer == TransferKind::fmpm && sim.config_.fmpm_order > 1) {
    graph.add({"fmpm",
               {geometry | FieldSet{Field::mass}, R::kBlocks | R::kClock},
               {{}, R::kGrid},
               [this] {
                 if (filtering) fmpm<Shape>();
               }});
  }
  // 5. particle velocity and displacement from the grid
  graph.add({"g2p",
             {geometry | FieldSet{Field::mass}, R::kGrid | R::kBlocks | R::kClock},
             {kVelocity, R::kDisplacement | R::kMechanical},
             [this] { g2p<Shape>(); }});
  // 6. MUSL: updated particle momentum back to the grid, nodal velocity. APIC particles hold
  // the grid velocity already, so the remap would return it unchanged and is left out.
  if (!apic) {
    graph.add({"remap",
               {geometry | kVelocity | FieldSet{Field::mass}, R::kBlocks | R::kBudget},
               {{}, R::kGrid | R::kBudget},
               [this] { remap<Shape>(); }});
  }
  // 7a. strain and spin increments, density (Eqs. 21, 23); APIC's C_p
  graph.add({"velocity_gradient",
             {geometry, R::kGrid | R::kBlocks | R::kClock},
             {kStrainIncrement | kSpinIncrement | affine | FieldSet{Field::rho}, 0},
             [this] { velocity_gradient<Shape>(); }});
  // 7b. constitutive update per material group (Eqs. 22, 35; EOS, strength, damage)
  graph.add({"constitutive",
             {kStrainIncrement | kSpinIncrement | FieldSet{Field::rho, Field::mass}, R::kClock},
             {kStress | models | FieldSet{Field::energy, Field::pressure, Field::soundspeed}, 0},
             [this] { constitutive(); }});
  // positions move only now: steps 6-7 needed the shape functions at x^n
  graph.add({"advance_positions", {{}, R::kDisplacement}, {kPosition, 0}, [this] {
               advance_positions();
             }});
  if (boundaries.has_outflow()) {
    graph.add({"outflow", {{}, 0}, {all, R::kBudget}, [this] { outflow(); }});
  }
  // energy accounts and the next time step (Eq. 34) are independent: they run concurrently
  graph.add(
      {"energy", {FieldSet{Field::mass, Field::energy}, R::kMechanical}, {{}, R::kBudget}, [this] {
         energy();
       }});
  graph.add({"time_step",
             {kVelocity | kPosition | kStress | FieldSet{Field::soundspeed}, 0},
             {{}, R::kClock},
             [this] { time_step(); }});
  graph.build();
}

template <class Shape>
void Simulation::Impl::sort() {
  ParticleStore& P = sim.particles_;
  const std::size_t n = P.size();
  owner_keys.resize(n);
  for (auto* v : {&dx, &dy, &dz, &kinetic, &potential, &kinetic_transferred}) v->resize(n);
  stencil_w.resize(n * kernels::Stencil<Shape>::kRow);
  stencil_off.resize(n);

  compute_keys<Shape>();
  check_finite();

  const unsigned every = sim.config_.reorder_interval;
  if (every > 0 && sim.clock_.step % every == 0) {
    // Physically re-order each material group by block key (stable, so deterministic): the
    // scatter and gather then stream through memory.
    order.resize(n);
    std::iota(order.begin(), order.end(), 0U);
    for (const Group& g : P.groups()) {
      std::stable_sort(
          order.begin() + static_cast<std::ptrdiff_t>(g.range.begin),
          order.begin() + static_cast<std::ptrdiff_t>(g.range.end),
          [&](std::uint32_t a, std::uint32_t b) { return owner_keys[a] < owner_keys[b]; });
    }
    P.permute(order);
    saved.permuted = saved.armed;  // a retake undoes it (restore_step)
    std::vector<std::uint64_t> sorted(n);
    for (std::size_t k = 0; k < n; ++k) sorted[k] = owner_keys[order[k]];
    owner_keys.swap(sorted);
  }
  // The particle ids make the order inside each block canonical (SparseGrid::assign).
  const auto ids = P.col(IField::id);
  bool rebuilt = false;
  if (contact) {
    const auto body = P.col(IField::body);
    rebuilt = grid.assign(owner_keys, {body.data(), body.size()}, {ids.data(), ids.size()});
  } else {
    rebuilt = grid.assign(owner_keys, {}, {ids.data(), ids.size()});
  }
  if (dist && (rebuilt || plan_version != decomp_version)) build_halo_plan();
  const double ih = inv_h();
  // Each particle's stencil at x^n, read by every transfer of the step (P2G, G2P, remap,
  // velocity gradient: kernels::StencilCache).
  const double* X[3] = {P.col(Field::x).data(), P.col(Field::y).data(), P.col(Field::z).data()};
  const double* size0 = P.col(Field::size0).data();
  const kernels::StencilCache cache = stencils(kernels::StencilCache::kStore);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kParticleGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      kernels::store_stencils<Shape>(X, size0, ih, r.begin(), r.end(), cache);
                    });
  if (driven) driven->scatter<Shape>(P, grid, stencils(kernels::StencilCache::kLoad), ih);
}

template <class Shape>
void Simulation::Impl::compute_keys() {
  ParticleStore& P = sim.particles_;
  const std::size_t n = P.size();
  owner_keys.resize(n);
  const double ih = inv_h();
  // First stencil node: floor(xi) for 2-wide stencils, floor(xi - 1/2) for 3-wide ones.
  const double shift = Shape::kWidth == 3 ? 0.5 : 0.0;
  const double limit = static_cast<double>(SparseGrid::kMaxBlockCoord * SparseGrid::kBlock);
  const double* X[3] = {P.col(Field::x).data(), P.col(Field::y).data(), P.col(Field::z).data()};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kParticleGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t p = r.begin(); p < r.end(); ++p) {
                        std::int64_t b[3];
                        for (int d = 0; d < 3; ++d) {
                          const double xi = X[d][p] * ih - shift;
                          // Out-of-range (or NaN) positions are caught by check_finite below;
                          // clamp so the key stays defined meanwhile.
                          const double c = std::isfinite(xi) ? std::clamp(xi, -limit, limit) : 0.0;
                          b[d] = static_cast<std::int64_t>(std::floor(c)) >> SparseGrid::kBlockBits;
                        }
                        owner_keys[p] = SparseGrid::key(b[0], b[1], b[2]);
                      }
                    });
}

// velocity: scatter m_p w_p with these particle velocities instead of v_p (momentum only; XPIC).
template <class Shape>
void Simulation::Impl::p2g(bool with_force, double* const* velocity) {
  ParticleStore& P = sim.particles_;
  kernels::P2GParticles in = mpm::p2g_inputs(P, inv_h(), with_force);
  if (velocity != nullptr) {
    in.vx = velocity[0];
    in.vy = velocity[1];
    in.vz = velocity[2];
  }
  const bool affine = sim.config_.transfer == TransferKind::apic;
  if (affine) vgrad_columns(P, in.vgrad);
  in.stencil = stencils(kernels::StencilCache::kLoad);
  if (with_force) {
    if (sim.config_.body_force) {
      for (auto* v : {&bx, &by, &bz}) v->assign(P.size(), 0.0);
      sim.config_.body_force(sim.clock_.time, P, bx.data(), by.data(), bz.data());
      in.bx = bx.data();
      in.by = by.data();
      in.bz = bz.data();
    }
    grid.clear_nodes();
  } else {
    auto& N = grid.nodes();
    std::fill(N.px.begin(), N.px.end(), 0.0);
    std::fill(N.py.begin(), N.py.end(), 0.0);
    std::fill(N.pz.begin(), N.pz.end(), 0.0);
  }
  if (grid.has_copies()) {
    p2g_bodies<Shape>(in, with_force);
    return;
  }
  // Colour by colour: blocks of one colour never share a node (see SparseGrid). On several
  // ranks, the partial sums of each colour at halo blocks are kept apart (halo_capture) and
  // added in colour order once every rank's partials are in (halo_reduce).
  const int fields = with_force ? kForceFields : kMomentumFields;
  for (int c = 0; c < SparseGrid::kColours; ++c) {
    if (dist) halo_zero(c, fields);
    const auto blocks = grid.colour(c);
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, blocks.size(), 1),
        [&](const tbb::blocked_range<std::size_t>& r) {
          kernels::P2GScratch scratch;
          for (std::size_t k = r.begin(); k < r.end(); ++k) {
            const std::uint32_t b = blocks[k];
            if (with_force && affine) {
              kernels::p2g_block<Shape, true, true>(in, grid.owned(b), grid.coord(b),
                                                    grid.neighbours(b), grid.nodes(), scratch);
            } else if (with_force) {
              kernels::p2g_block<Shape, true>(in, grid.owned(b), grid.coord(b), grid.neighbours(b),
                                              grid.nodes(), scratch);
            } else {
              kernels::p2g_block<Shape, false>(in, grid.owned(b), grid.coord(b), grid.neighbours(b),
                                               grid.nodes(), scratch);
            }
          }
        });
    if (dist) halo_capture(c, fields);
  }
  // The force-carrying scatter's exchange is its own stage ("halo"); the momentum-only scatters
  // (remap, XPIC passes) exchange here.
  if (dist && !with_force) halo_reduce(kMomentumFields);
}

// P2G where bodies meet: the particles of an owner block scatter in runs that share one
// neighbour list (one per body next to a meeting block), into their own body's copies; runs
// that reach copies also scatter their mass gradient (the contact normal). Same colouring as
// p2g, so the sums at every node are still formed in a fixed order.
template <class Shape>
void Simulation::Impl::p2g_bodies(const kernels::P2GParticles& in, bool with_force) {
  const bool affine = sim.config_.transfer == TransferKind::apic;
  const auto first_copy = static_cast<std::uint32_t>(grid.shared_blocks());
  for (int c = 0; c < SparseGrid::kColours; ++c) {
    const auto blocks = grid.colour(c);
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, blocks.size(), 1),
        [&](const tbb::blocked_range<std::size_t>& r) {
          kernels::P2GScratch scratch;
          for (std::size_t k = r.begin(); k < r.end(); ++k) {
            const std::uint32_t b = blocks[k];
            for_each_list_run(grid, b, [&](auto run, std::uint32_t list) {
              const std::uint32_t* nb = grid.list(list);
              if (with_force && affine) {
                kernels::p2g_block<Shape, true, true>(in, run, grid.coord(b), nb, grid.nodes(),
                                                      scratch);
              } else if (with_force) {
                kernels::p2g_block<Shape, true>(in, run, grid.coord(b), nb, grid.nodes(), scratch);
              } else {
                kernels::p2g_block<Shape, false>(in, run, grid.coord(b), nb, grid.nodes(), scratch);
              }
              if (with_force && list != b * 8) {
                kernels::mass_gradient_block<Shape>(in, run, grid.coord(b), nb, first_copy,
                                                    grid.nodes(), scratch);
              }
            });
          }
        });
  }
}

void Simulation::Impl::grid_update() {
  const Clock& clk = sim.clock_;
  const double dt_kick = 0.5 * (clk.dt_prev + dt_step);  // leapfrog dt^n (Fig. 16)
  // The resolved kinetic energy of the P2G, before the mirror folds images in and before the
  // boundary conditions and the momentum update change the nodes.
  unresolved_kinetic();
  // (several ranks: the owners mirrored the halo blocks, halo_reduce)
  if (!dist) boundaries.mirror(grid, mpm::Boundaries::kMassMomentumForce);
  boundaries.integrate(grid, sim.config_.gravity, dt_kick, empty_mass, dist ? &halo.owned : nullptr,
                       &removed_sum);
  // Driven bodies' nodes take the prescribed velocity before contact sees them (driven.hpp).
  if (driven) sim.energy_.boundary_work -= driven->constrain(grid, dt_kick);
  if (grid.has_copies()) {
    // Contact after the momentum update (end of step 4): G2P hands the particles the corrected
    // velocity and acceleration. What the correction takes out of the nodal kinetic energy is
    // not booked: it is not what the FLIP particles lose (booking it gave +33% error in the lab
    // impact and +400% in the contact test), so EnergyBudget::error() shows the contact's net
    // dissipation (docs/verification.md, contact).
    contact->resolve(grid, boundaries, dt_kick, empty_mass);
    // A ghost node and its partner across a symmetry plane (or fixed wall) need not lie in
    // blocks that meet the same bodies, so the correction may treat them differently; the
    // ghosts take the image of the corrected field again.
    boundaries.mirror_ghosts(grid);
  }
  // The kinetic energy a constraint takes out of the nodal momentum leaves the particles only
  // when they take the grid velocity (APIC). FLIP particles keep their own velocity and feel a
  // wall only through the constrained acceleration, so there is nothing to book: an ideal wall
  // does no work, and booking the nodal loss made a clamped bar that keeps its energy report a
  // 2.4% "boundary work" drift (scenes/verification/vibrating-bar.toml).
  // The same holds for the share of the grid velocity that PIC, XPIC and the FLIP/PIC blend hand
  // the particles.
  // (booked in finish_step, summed over the ranks)
}

// -sum_I |p_I|^2 / (2 m_I) over the nodes of the step's force-carrying P2G, p_I and m_I the
// lumped momentum sum_p m_p N_I(x_p) v_p and mass sum_p m_p N_I(x_p) (Eqs. 29, 32), added to
// the particles' sum_p m_p |v_p|^2/2 of the same velocities (energy()) it is the kinetic energy
// the grid does not represent: >= 0, since with sum_I N_I(x_p) = 1 the nodal velocity p_I/m_I is
// a mass-weighted mean of the v_p (Cauchy-Schwarz: |p_I|^2 <= m_I sum_p m_p N_I |v_p|^2). It is
// exactly the kinetic energy the grid velocity lacks, and so the least one PIC transfer
// v_p <- sum_I N_I p_I/m_I takes away (the gather loses more: sum_p m_p |S V|^2/2 <=
// sum_I m_I |V_I|^2/2 by the same argument). Zero for a rigid translation. Body copies hold each
// body's own field where bodies meet (the shared nodes there are empty), so the sum is over every
// body's field. One rank: the raw scatter, before the mirror of symmetry/fixed planes folds images
// in, so the nodes beyond a plane hold only the real particles' own weights and nothing is counted
// twice. Several ranks: halo_reduce sums each node on its owner, from the same complete sums before
// the same mirror, so the value is the one process's, bit for bit (an exact sum).
void Simulation::Impl::unresolved_kinetic() {
  if (dist) return;  // summed in halo_reduce, before its mirror
  auto& N = grid.nodes();
  unresolved_sum = node_unresolved(
      grid.blocks(), [](std::uint32_t) { return true; },
      [&](std::uint32_t b, int f) {
        double* const a[4] = {N.mass.data(), N.px.data(), N.py.data(), N.pz.data()};
        return a[f] + std::size_t{b} * SparseGrid::kBlockNodes;
      });
}

double Simulation::Impl::filtered_share() const {
  switch (sim.config_.transfer) {
    case TransferKind::flip:
      return sim.config_.pic_fraction;
    case TransferKind::apic:
      return 1.0;
    case TransferKind::xpic:
    case TransferKind::fmpm:
      return filtering ? 1.0 : 0.0;  // FLIP on the steps filter_every leaves out
  }
  return 0.0;
}

// Periodic filtering (the PeriodicXPIC custom task of NairnMPM/OSParticulas: FLIP on most
// steps, the XPIC(k) or FMPM(k) update every N-th): the step that leaves Clock::step = n + 1
// filters when n + 1 is a multiple of N. The counter is in the checkpoint, so a resumed run
// keeps the phase; a retaken step has the same counter, so it decides the same way.
bool Simulation::Impl::filters_step(std::uint64_t step) const {
  return (step + 1) % static_cast<std::uint64_t>(sim.config_.filter_every) == 0;
}

// The extra grid-particle-grid passes of XPIC and FMPM, shared: passes 2..terms of the series
// in A = M_L^{-1} M_c = S+ S. On entry v^{n+1} (after grid_update's boundary conditions) is in
// the momentum arrays; it is kept aside in xpic_v while those arrays become the passes'
// workspace, and update(k, i) runs for every node after pass k with (A xpic_term)_i in the
// momentum arrays: it writes the next pass's input into xpic_term, which the caller fills
// before the first pass (series_arrays sizes the arrays). One pass is the gather S of xpic_term to
// the points (kernels::gather_velocity, from the stencils of this step) and the momentum-only
// scatter of the MUSL remap (same colouring, so node sums keep their canonical order), with the
// remap's boundary conditions (mirror, wall velocities): S+ includes them, as in both papers. The
// caller swaps the arrays back.
template <class Shape, class Update>
void Simulation::Impl::series_passes(int terms, Update&& update) {
  ParticleStore& P = sim.particles_;
  auto& N = grid.nodes();
  const std::size_t nodes = N.px.size();
  const std::size_t n = P.size();
  kernels::G2PParticles in = mpm::g2p_inputs(P, inv_h(), nullptr, nullptr, nullptr);
  in.stencil = stencils(kernels::StencilCache::kLoad);
  double* w[3] = {xpic_w[0].data(), xpic_w[1].data(), xpic_w[2].data()};
  for (int k = 2; k <= terms; ++k) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kParticleGrain),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t p = r.begin(); p < r.end(); ++p) {
                          kernels::gather_velocity<Shape>(in, p, grid.coord(grid.owner_of(p)),
                                                          grid.particle_neighbours(p),
                                                          xpic_term[0].data(), xpic_term[1].data(),
                                                          xpic_term[2].data(), w[0], w[1], w[2]);
                        }
                      });
    p2g<Shape>(false, w);
    if (!dist) boundaries.mirror(grid, mpm::Boundaries::kMomentum);
    boundaries.velocities(grid, empty_mass);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nodes, 4096),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t i = r.begin(); i < r.end(); ++i) update(k, i);
                      });
  }
}

namespace {
// Sets v^{n+1} aside in `kept` and sizes the passes' arrays (XPIC, FMPM).
template <class Vec, class AVec>
void series_arrays(std::vector<double>* (&mom)[3], Vec (&kept)[3], Vec (&term)[3], Vec (&target)[3],
                   AVec (&w)[3], std::size_t nodes, std::size_t particles, bool with_target) {
  for (int d = 0; d < 3; ++d) {
    kept[d].swap(*mom[d]);  // v^{n+1} aside; the momentum arrays become the passes' workspace
    mom[d]->resize(nodes);
    term[d].resize(nodes);
    if (with_target) target[d].resize(nodes);
    w[d].resize(particles);
  }
}

template <class F>
void node_loop(std::size_t nodes, F&& body) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nodes, 4096),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i < r.end(); ++i) body(i);
                    });
}
}  // namespace

// XPIC(m), Hammerquist & Nairn (2017): V*_m = sum_{k=1..m} (-1)^{k+1} C(m,k) (S+ S)^{k-1} V^L,
// with V^L = S+ v_p the lumped grid velocity of the particles at the start of the step and
// (S+ S V)_I = (1/m_I) sum_p m_p N_I(x_p) sum_J N_J(x_p) V_J one grid-particle-grid pass. It is
// the grid form of their particle update v_p <- v_p - (I - S S+)^m v_p + S a dt: the
// PIC filter's projection I - S S+ applied m times, so velocity noise in the null space of S+ is
// removed while what the grid can represent loses only its (I - S+ S)^m part. The passes are
// series_passes. The term C(m,k) (S+S)^{k-1} V^L is formed recursively with the ratio
// C(m,k)/C(m,k-1) = (m-k+1)/k, as in the authors' own code (NairnMPM, XPICExtrapolationTask).
// G2P then takes S (V*_m + a dt) = S (v^{n+1} + V*_m - V^L), which is v^{n+1} itself, and so
// PIC bitwise, for m = 1.
template <class Shape>
void Simulation::Impl::xpic() {
  auto& N = grid.nodes();
  const std::size_t nodes = N.px.size();
  const int m = sim.config_.xpic_order;
  const double dt = 0.5 * (sim.clock_.dt_prev + dt_step);  // the kick of grid_update
  std::vector<double>* mom[3] = {&N.px, &N.py, &N.pz};
  const std::vector<double>* acc[3] = {&N.fx, &N.fy, &N.fz};
  series_arrays(mom, xpic_v, xpic_term, xpic_target, xpic_w, nodes, sim.particles_.size(), true);
  // k = 1: C(m,1) V^L, with V^L = v^{n+1} - a dt (the lumped velocity after the boundary
  // conditions of grid_update). xpic_target accumulates V*_m - V^L.
  const double md = static_cast<double>(m);
  node_loop(nodes, [&](std::size_t i) {
    for (int d = 0; d < 3; ++d) {
      const double vl = xpic_v[d][i] - dt * (*acc[d])[i];
      xpic_term[d][i] = md * vl;
      xpic_target[d][i] = (md - 1.0) * vl;
    }
  });
  series_passes<Shape>(m, [&](int k, std::size_t i) {
    const double ratio = static_cast<double>(m - k + 1) / static_cast<double>(k);
    const double sign = k % 2 == 0 ? -1.0 : 1.0;  // (-1)^{k+1}
    for (int d = 0; d < 3; ++d) {
      const double t = ratio * (*mom[d])[i];
      xpic_term[d][i] = t;
      xpic_target[d][i] += sign * t;
    }
  });
  node_loop(nodes, [&](std::size_t i) {
    for (int d = 0; d < 3; ++d) xpic_target[d][i] += xpic_v[d][i];
  });
  for (int d = 0; d < 3; ++d) xpic_v[d].swap(*mom[d]);  // v^{n+1} back for the displacement
}

// FMPM(k), Nairn & Hammerquist (2021), CMAME 377, 113667, revised in Nairn (2026), arXiv
// 2604.07307: the grid velocity solves M_c v = p^{n+1} with the full (consistent) mass matrix
// M_c, (M_c)_IJ = sum_p m_p N_I(x_p) N_J(x_p), approximately, by the order-k series
//   v_F = sum_{i=0..k-1} (I - M_L^{-1} M_c)^i M_L^{-1} p^{n+1},
// M_L the lumped (diagonal) mass matrix, M_L^{-1} p^{n+1} = v^{n+1} the lumped velocity of
// grid_update and M_L^{-1} M_c = S+ S one pass. By sum_{i<k} (I - A)^i = sum_{j=1..k} (-1)^{j+1}
// C(k,j) A^{j-1} it is XPIC's series, applied to v^{n+1} (after the force) instead of to V^L;
// XPIC(k) adds a dt unfiltered. Here it is summed in the nested (Neumann) form
//   v^(1) = v^{n+1},  v^(j) = v^(1) + (I - A) v^(j-1),  v_F = v^(k),
// the same k - 1 passes, with round-off ~ k eps instead of the ~ 2^k eps of the alternating
// binomial sum (C(32,16) = 6e8), and a uniform velocity (A v = v) is kept to round-off at every
// order. v_F replaces v^{n+1} in the momentum arrays: G2P gives the particle v_p = S v_F (the
// FMPM particle update: v_p^{n+1} = S v^(k), no FLIP increment) and the displacement S v_F dt.
// NairnMPM's FMPM moves a particle by the mean of its old and new velocities, both S v^(k), so
// the position follows the filtered velocity; in this code's staggered leapfrog the particle
// velocity is v^{n+1/2} itself and x^{n+1} = x^n + dt S v_F is that update. FMPM(1) therefore
// is PIC (pic_fraction 1) bitwise: no pass runs and v_F = v^{n+1}.
template <class Shape>
void Simulation::Impl::fmpm() {
  auto& N = grid.nodes();
  const std::size_t nodes = N.px.size();
  std::vector<double>* mom[3] = {&N.px, &N.py, &N.pz};
  series_arrays(mom, xpic_v, xpic_term, xpic_target, xpic_w, nodes, sim.particles_.size(), false);
  node_loop(nodes, [&](std::size_t i) {
    for (int d = 0; d < 3; ++d) xpic_term[d][i] = xpic_v[d][i];  // v^(1) = M_L^{-1} p^{n+1}
  });
  series_passes<Shape>(sim.config_.fmpm_order, [&](int, std::size_t i) {
    for (int d = 0; d < 3; ++d) {
      xpic_term[d][i] = xpic_v[d][i] + (xpic_term[d][i] - (*mom[d])[i]);  // v1 + (I - A) v
    }
  });
  for (int d = 0; d < 3; ++d) xpic_term[d].swap(*mom[d]);  // v_F where G2P reads v^{n+1}
}

template <class Shape>
void Simulation::Impl::g2p() {
  ParticleStore& P = sim.particles_;
  kernels::G2PParticles in = mpm::g2p_inputs(P, inv_h(), dx.data(), dy.data(), dz.data());
  in.stencil = stencils(kernels::StencilCache::kLoad);
  in.dt_velocity = 0.5 * (sim.clock_.dt_prev + dt_step);
  in.dt_position = dt_step;
  // The share of the filtered grid velocity in the particle update (TransferKind).
  in.pic_fraction = filtered_share();
  if (sim.config_.transfer == TransferKind::xpic && sim.config_.xpic_order > 1 && filtering) {
    in.fvx = xpic_target[0].data();
    in.fvy = xpic_target[1].data();
    in.fvz = xpic_target[2].data();
  }
  const double* mass = P.col(Field::mass).data();
  const double half_dt_prev = 0.5 * sim.clock_.dt_prev;
  const Vec3 g = sim.config_.gravity;
  // Velocity at t^n, v^{n-1/2} + a dt^{n-1/2}/2, makes the kinetic energy time-centred with
  // the internal energy (second-order energy error).
  const double w = in.dt_velocity > 0 ? half_dt_prev / in.dt_velocity : 0.0;
  const auto energies = [&](std::size_t p, const double(&v0)[3]) {
    const double vn[3] = {v0[0] + w * (in.vx[p] - v0[0]), v0[1] + w * (in.vy[p] - v0[1]),
                          v0[2] + w * (in.vz[p] - v0[2])};
    kinetic[p] = 0.5 * mass[p] * (vn[0] * vn[0] + vn[1] * vn[1] + vn[2] * vn[2]);
    kinetic_transferred[p] = 0.5 * mass[p] * (v0[0] * v0[0] + v0[1] * v0[1] + v0[2] * v0[2]);
    potential[p] = -mass[p] * (g.x() * in.x[p] + g.y() * in.y[p] + g.z() * in.z[p]);
  };
  for_each_run<kernels::G2PWindow>(
      grid, [&](std::span<const std::uint32_t> run, const SparseGrid::Coord& owner,
                const std::uint32_t* nb, kernels::G2PWindow& win) {
        kernels::g2p_block<Shape>(in, run, owner, nb, grid.nodes(), win, energies);
      });
  if (driven) driven->set_particles(P, dx.data(), dy.data(), dz.data(), kinetic.data(), dt_step);
}

template <class Shape>
void Simulation::Impl::remap() {
  // Where bodies meet, the strain rate takes the step-4 velocities of the body fields (USL, the
  // velocities the contact correction and the forces acted on), not the remapped ones: FLIP
  // particle velocities remapped to two body fields disagree with the corrected fields, and the
  // strain rate built from them made stress that no kinetic energy paid for. A sphere bouncing
  // off a plate left with +31% energy; two cubes meeting head-on, with the contact correction
  // applied to the remapped fields instead, with 2.2x (docs/verification.md, contact). Keeping
  // the step-4 velocities there never created energy in any test (as APIC, which has no remap).
  const bool contact_nodes = grid.has_copies();
  const std::size_t g0 = grid.shared_blocks() * SparseGrid::kBlockNodes;
  auto& N = grid.nodes();
  if (contact_nodes) {
    const auto n = static_cast<std::ptrdiff_t>(N.px.size() - g0);
    step4_velocity.resize(3 * static_cast<std::size_t>(n));
    const auto at = step4_velocity.begin();
    std::copy(N.px.begin() + static_cast<std::ptrdiff_t>(g0), N.px.end(), at);
    std::copy(N.py.begin() + static_cast<std::ptrdiff_t>(g0), N.py.end(), at + n);
    std::copy(N.pz.begin() + static_cast<std::ptrdiff_t>(g0), N.pz.end(), at + 2 * n);
  }
  p2g<Shape>(false);
  if (!dist) boundaries.mirror(grid, mpm::Boundaries::kMomentum);
  // The remapped velocities only feed the strain rate (MUSL); no particle velocity changes here.
  boundaries.velocities(grid, empty_mass);
  if (contact_nodes) {
    const auto n = static_cast<std::ptrdiff_t>(N.px.size() - g0);
    const auto at = step4_velocity.begin();
    std::copy(at, at + n, N.px.begin() + static_cast<std::ptrdiff_t>(g0));
    std::copy(at + n, at + 2 * n, N.py.begin() + static_cast<std::ptrdiff_t>(g0));
    std::copy(at + 2 * n, at + 3 * n, N.pz.begin() + static_cast<std::ptrdiff_t>(g0));
  }
}

template <class Shape>
void Simulation::Impl::velocity_gradient() {
  ParticleStore& P = sim.particles_;
  kernels::GradientParticles in = mpm::gradient_inputs(P, inv_h(), dt_step);
  in.stencil = stencils(kernels::StencilCache::kLoad);
  if (sim.config_.transfer == TransferKind::apic) vgrad_columns(P, in.vgrad);
  for_each_run<kernels::GradientWindow>(
      grid, [&](std::span<const std::uint32_t> run, const SparseGrid::Coord& owner,
                const std::uint32_t* nb, kernels::GradientWindow& win) {
        kernels::velocity_gradient_block<Shape>(in, run, owner, nb, grid.nodes(), win);
      });
}

void Simulation::Impl::constitutive() {
  const ConstitutiveContext ctx{dt_step, sim.config_.cell_size, sim.config_.viscosity};
  for (const Group& g : sim.particles_.groups()) {
    if (g.range.empty()) continue;
    sim.materials_[static_cast<std::size_t>(g.material)]->update(sim.particles_, g.range, ctx);
  }
}

void Simulation::Impl::advance_positions() {
  ParticleStore& P = sim.particles_;
  double* X[3] = {P.col(Field::x).data(), P.col(Field::y).data(), P.col(Field::z).data()};
  const double* D[3] = {dx.data(), dy.data(), dz.data()};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, P.size(), kParticleGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (int d = 0; d < 3; ++d) {
                        for (std::size_t p = r.begin(); p < r.end(); ++p) X[d][p] += D[d][p];
                      }
                    });
}

void Simulation::Impl::outflow() {
  ParticleStore& P = sim.particles_;
  std::vector<std::uint8_t> leaving(P.size(), 0);
  const auto x = P.col(Field::x), y = P.col(Field::y), z = P.col(Field::z);
  const auto m = P.col(Field::mass), e = P.col(Field::energy);
  const auto vx = P.col(Field::vx), vy = P.col(Field::vy), vz = P.col(Field::vz);
  const Vec3 g = sim.config_.gravity;
  parallel::ExactSum carried, carried_internal;
  for (std::size_t p = 0; p < P.size(); ++p) {
    if (!boundaries.outside_outflow(Vec3(x[p], y[p], z[p]))) continue;
    leaving[p] = 1;
    carried_internal.add(m[p] * e[p]);
    carried.add(0.5 * m[p] * (vx[p] * vx[p] + vy[p] * vy[p] + vz[p] * vz[p]) + m[p] * e[p] -
                m[p] * (g.x() * x[p] + g.y() * y[p] + g.z() * z[p]));
  }
  if (std::find(leaving.begin(), leaving.end(), std::uint8_t{1}) == leaving.end()) return;
  keep_leaving(leaving);
  P.remove_if(leaving);
  // On several ranks one rank may lose all its particles; finish_step checks the total.
  if (P.size() == 0 && !dist) {
    throw NumericalError("every particle has left through the outflow boundaries", 0,
                         sim.clock_.step);
  }
  carried_sum = carried;  // booked in finish_step, summed over the ranks
  // The internal energy reported with this step is the sum made at the end of the previous one
  // (internal_next), which still holds the departed particles: without this their internal
  // energy would count twice in this step's budget, once there and once in `carried` (a
  // single-row spike of the energy error, +0.3 to +0.5 % in the lab impact), and drop out of the
  // internal sum one row later. Kinetic and potential energy are dropped from this step's sums
  // below, so all three leave the budget in the step that books them as outflow.
  carried_internal_sum = carried_internal;
  // The particles still carry this step's mechanical energy in kinetic[]/potential[]; drop the
  // departed ones so the energy sum below matches the remaining particles.
  std::size_t k = 0;
  for (std::size_t p = 0; p < leaving.size(); ++p) {
    if (leaving[p]) continue;
    kinetic[k] = kinetic[p];
    potential[k] = potential[p];
    ++k;
  }
  kinetic.resize(k);
  potential.resize(k);
}

void Simulation::Impl::energy() {
  ParticleStore& P = sim.particles_;
  const auto m = P.col(Field::mass), e = P.col(Field::energy);
  // This rank's exact sums; finish_step combines them over the ranks and books them.
  // One pass for both kinetic sums; kinetic_transferred keeps the particles outflow removed
  // (their P2G momentum is on the nodes unresolved_kinetic() summed), so it may be longer.
  const std::size_t nk = kinetic.size(), nt = kinetic_transferred.size();
  using Pair = std::array<parallel::ExactSum, 2>;
  const Pair both = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, std::max(nk, nt), kParticleGrain), Pair{},
      [&](const tbb::blocked_range<std::size_t>& r, Pair acc) {
        for (std::size_t p = r.begin(); p < r.end(); ++p) {
          if (p < nk) acc[0].add(kinetic[p]);
          if (p < nt) acc[1].add(kinetic_transferred[p]);
        }
        return acc;
      },
      [](Pair a, const Pair& b) {
        a[0].add(b[0]);
        a[1].add(b[1]);
        return a;
      });
  kinetic_sum = both[0];
  transferred_sum = both[1];
  potential_sum = exact_sum(potential.size(), [&](std::size_t p) { return potential[p]; });
  internal_sum = exact_sum(P.size(), [&](std::size_t p) { return m[p] * e[p]; });
}

void Simulation::Impl::check_finite() const {
  const ParticleStore& P = sim.particles_;
  const std::size_t n = P.size();
  static constexpr Field kChecked[] = {Field::x,   Field::y,      Field::z,         Field::vx,
                                       Field::vy,  Field::vz,     Field::sxx,       Field::syy,
                                       Field::szz, Field::sxy,    Field::syz,       Field::sxz,
                                       Field::rho, Field::energy, Field::soundspeed};
  // The first offending particle (lowest index), whatever the thread count.
  const std::size_t bad = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, n, kParticleGrain), n,
      [&](const tbb::blocked_range<std::size_t>& r, std::size_t found) {
        // A value is not finite when its exponent bits are all set (IEEE 754). OR-ing that test
        // over the chunk has no branch per element and vectorises; the search for the first
        // offender runs only in a chunk that has one (rare: the run is about to stop).
        constexpr std::uint64_t kExponent = 0x7ff0000000000000ULL;
        std::uint64_t any = 0;
        for (const Field f : kChecked) {
          const double* c = P.col(f).data();
          for (std::size_t p = r.begin(); p < r.end(); ++p) {
            any |= static_cast<std::uint64_t>((std::bit_cast<std::uint64_t>(c[p]) & kExponent) ==
                                              kExponent);
          }
        }
        if (any == 0) return found;
        for (const Field f : kChecked) {
          const auto c = P.col(f);
          for (std::size_t p = r.begin(); p < std::min(r.end(), found); ++p) {
            if (!std::isfinite(c[p])) {
              found = p;
              break;
            }
          }
        }
        return found;
      },
      [](std::size_t a, std::size_t b) { return std::min(a, b); });
  if (bad == n) return;
  for (const Field f : kChecked) {
    const double v = P.col(f)[bad];
    if (!std::isfinite(v)) {
      const auto ids = P.col(IField::id);
      throw NumericalError(
          fmt::format("non-finite {} = {} at particle {} (id {}) at step {}, t = {:.6e} s",
                      name_of(f), v, bad, ids[bad], sim.clock_.step, sim.clock_.time),
          bad, sim.clock_.step);
    }
  }
}

double Simulation::Impl::stable_dt() {
  const double fast = dist ? comm.max(fastest_local()) : fastest_local();
  const SolverConfig& cfg = sim.config_;
  if (!(fast > 0.0)) return cfg.dt_max;  // nothing moves and nothing can: any step is stable
  return std::min(cfg.cfl * cfg.cell_size / fast, cfg.dt_max);
}

double Simulation::Impl::fastest_local() const {
  const ParticleStore& P = sim.particles_;
  const auto c = P.col(Field::soundspeed);
  const auto vx = P.col(Field::vx), vy = P.col(Field::vy), vz = P.col(Field::vz);
  // max_p (c_p + |v_p|) of Eq. 34; max is exact, so the reduction order does not matter.
  const double fast_max = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, P.size(), kParticleGrain), 0.0,
      [&](const tbb::blocked_range<std::size_t>& r, double acc) {
        for (std::size_t p = r.begin(); p < r.end(); ++p) {
          acc = std::max(acc, c[p] + std::sqrt(vx[p] * vx[p] + vy[p] * vy[p] + vz[p] * vz[p]));
        }
        return acc;
      },
      [](double a, double b) { return std::max(a, b); });
  return fast_max;
}

void Simulation::Impl::time_step() {
  if (fault.kind != 0 && fault.rank == comm.rank() && fault.step == sim.clock_.step + 1) {
    if (fault.kind == 2) {
      throw std::runtime_error(
          fmt::format("injected fault (SHATTER_FAULT_INJECT) at step {}", fault.step));
    }
    if (sim.particles_.size() > 0) sim.particles_.col(Field::vx)[0] = std::nan("");
  }
  if (dist) {
    // A failure is decided for all ranks at once in finish_step, so that no rank waits for one
    // that left.
    try {
      check_finite();
    } catch (const NumericalError& e) {
      failure = fmt::format("rank {}: {}", comm.rank(), e.what());
      failure_particle = e.particle();
    }
  } else {
    check_finite();
  }
  Clock& clk = sim.clock_;
  clk.time += dt_step;
  clk.dt_prev = dt_step;
  ++clk.step;
  fastest = fastest_local();
}

// After the step's graph: the sums and the next time step over all ranks (exact: integer limb
// sums and a maximum), then the same decisions on every rank.
void Simulation::Impl::finish_step() {
  EnergyBudget& E = sim.energy_;
  Clock& clk = sim.clock_;
  double flags[3] = {fastest, failure.empty() ? 0.0 : 1.0, sim.particles_.size() > 0 ? 1.0 : 0.0};
  if (dist) comm.max(flags);
  if (flags[1] > 0.0) {
    const std::string what = failure.empty()
                                 ? std::string("numerical failure on another rank (reported there)")
                                 : failure;
    failure.clear();
    throw NumericalError(what, failure_particle, clk.step);
  }
  if (flags[2] == 0.0) {
    throw NumericalError("every particle has left through the outflow boundaries", 0, clk.step);
  }
  // The unresolved sum: the transferred kinetic energy plus the (negative) nodal terms, exactly.
  unresolved_sum.add(transferred_sum);
  constexpr int kSums = 8;
  parallel::ExactSum* sums[kSums] = {&kinetic_sum,     &potential_sum,        &internal_sum,
                                     &carried_sum,     &carried_internal_sum, &removed_sum,
                                     &transferred_sum, &unresolved_sum};
  double v[kSums];
  if (dist) {
    constexpr int L = parallel::ExactSum::kLimbs;
    std::vector<std::int64_t> limbs(kSums * L + kSums);
    for (int k = 0; k < kSums; ++k) {
      sums[k]->normalise();
      std::copy(sums[k]->limbs().begin(), sums[k]->limbs().end(), limbs.begin() + k * L);
      const double sp = sums[k]->special();
      limbs[kSums * L + static_cast<std::size_t>(k)] = sp != 0.0 || std::isnan(sp) ? 1 : 0;
    }
    comm.sum(limbs);
    for (int k = 0; k < kSums; ++k) {
      std::copy(limbs.begin() + k * L, limbs.begin() + (k + 1) * L, sums[k]->limbs().begin());
      sums[k]->special() = limbs[kSums * L + static_cast<std::size_t>(k)] > 0 ? std::nan("") : 0.0;
    }
  }
  for (int k = 0; k < kSums; ++k) {
    v[k] = sums[k]->value();
    *sums[k] = parallel::ExactSum{};
  }
  E.kinetic = v[0];
  E.potential = v[1];
  E.transferred_kinetic = v[6];
  E.unresolved_kinetic = v[7];
  // Internal energy at t^n was summed at the end of the previous step; what left through an
  // outflow face in this step is booked as outflow instead (see outflow()).
  E.internal = internal_next - v[4];
  internal_next = v[2];
  E.outflow += v[3];
  E.scale = std::max(E.scale, std::abs(E.kinetic) + std::abs(E.internal));
  const double taken = filtered_share();
  if (taken > 0.0) E.boundary_work += taken * v[5];
  fastest = flags[0];
  const SolverConfig& cfg = sim.config_;
  clk.dt = fastest > 0.0 ? std::min(cfg.cfl * cfg.cell_size / fastest, cfg.dt_max) : cfg.dt_max;
  check_new_time_step(clk, sim.config_.dt_min, "no sound speed and no motion, and no dt_max set");
}

double Simulation::Impl::global(parallel::ExactSum s) const {
  if (dist) {
    s.normalise();
    std::vector<std::int64_t> limbs(s.limbs().begin(), s.limbs().end());
    const double sp = s.special();
    limbs.push_back(sp != 0.0 || std::isnan(sp) ? 1 : 0);
    comm.sum(limbs);
    std::copy(limbs.begin(), limbs.end() - 1, s.limbs().begin());
    s.special() = limbs.back() > 0 ? std::nan("") : 0.0;
  }
  return s.value();
}

// ---------------------------------------------------------------------------------------------
// Distributed runs (docs/mpi.md)

template <class Shape>
void Simulation::Impl::distribute() {
  // Every rank holds every particle here: the first cut needs no communication.
  compute_keys<Shape>();
  std::vector<std::uint64_t> keys(owner_keys);
  std::sort(keys.begin(), keys.end());
  std::vector<std::pair<std::uint64_t, std::int64_t>> weights;
  for (const std::uint64_t k : keys) {
    if (weights.empty() || weights.back().first != k) weights.emplace_back(k, 0);
    ++weights.back().second;
  }
  decomp.build(std::move(weights), comm.size());
  ++decomp_version;
  ParticleStore& P = sim.particles_;
  std::vector<std::uint8_t> keep(P.size());
  for (std::size_t p = 0; p < P.size(); ++p) {
    keep[p] = decomp.rank_of(owner_keys[p]) == comm.rank() ? 1 : 0;
  }
  P = parallel::merge_particles(P, keep, {});
}

void Simulation::Impl::rebalance_if_needed() {
  if (sim.clock_.step % rebalance_every != 0) return;
  const std::int64_t mine[1] = {static_cast<std::int64_t>(owner_keys.size())};
  const auto counts = comm.allgather(mine);
  std::int64_t total = 0, most = 0;
  for (const std::int64_t c : counts) {
    total += c;
    most = std::max(most, c);
  }
  const double mean = static_cast<double>(total) / static_cast<double>(counts.size());
  if (!(static_cast<double>(most) > imbalance * mean)) return;
  // Recut from every rank's (owner block, particles) pairs; ownership moves, values do not.
  std::vector<std::uint64_t> keys(owner_keys);
  std::sort(keys.begin(), keys.end());
  std::vector<std::int64_t> flat;
  for (std::size_t k = 0; k < keys.size(); ++k) {
    if (k == 0 || keys[k] != keys[k - 1]) {
      flat.push_back(std::bit_cast<std::int64_t>(keys[k]));
      flat.push_back(0);
    }
    ++flat.back();
  }
  const auto all = comm.allgather(flat);
  std::vector<std::pair<std::uint64_t, std::int64_t>> weights;
  weights.reserve(all.size() / 2);
  for (std::size_t k = 0; k + 1 < all.size(); k += 2) {
    weights.emplace_back(std::bit_cast<std::uint64_t>(all[k]), all[k + 1]);
  }
  decomp.build(std::move(weights), comm.size());
  ++decomp_version;
  ++rebalances;
}

template <class Shape>
void Simulation::Impl::migrate() {
  ParticleStore& P = sim.particles_;
  compute_keys<Shape>();
  rebalance_if_needed();
  const auto ranks = static_cast<std::size_t>(comm.size());
  const auto me = static_cast<std::size_t>(comm.rank());
  std::vector<std::vector<std::uint32_t>> leaving(ranks);
  std::vector<std::uint8_t> keep(P.size(), 1);
  for (std::size_t p = 0; p < P.size(); ++p) {
    const auto r = static_cast<std::size_t>(decomp.rank_of(owner_keys[p]));
    if (r == me) continue;
    keep[p] = 0;
    leaving[r].push_back(static_cast<std::uint32_t>(p));
  }
  std::vector<parallel::Bytes> send(ranks);
  bool moved = false;
  for (std::size_t r = 0; r < ranks; ++r) {
    if (leaving[r].empty()) continue;
    send[r] = parallel::pack_particles(P, leaving[r]);
    moved = true;
  }
  std::vector<parallel::Bytes> received = comm.exchange(send, &migrate_traffic);
  received[me].clear();
  for (const auto& b : received) moved = moved || !b.empty();
  // Arrivals go to the end of their group; their place in the store changes no sum (the order
  // inside a block is by id, the energy sums are exact).
  if (!moved) return;
  ParticleStore merged = parallel::merge_particles(P, keep, received);
  if (saved.armed) {
    // The store at t^n, for a retake (restore_step); kept rather than freed.
    saved.store = std::move(P);
    saved.whole = true;
  }
  P = std::move(merged);
}

void Simulation::Impl::build_halo_plan() {
  plan_version = decomp_version;
  const int me = comm.rank();
  const std::size_t nb = grid.blocks();
  halo.blocks.clear();
  halo.owner.clear();
  halo.slot.clear();
  for (auto& c : halo.by_colour) c.clear();
  halo.owned.assign(nb, 0);
  halo.ghosts_to.assign(static_cast<std::size_t>(comm.size()), 0);
  std::int32_t slots = 0;
  for (std::uint32_t b = 0; b < nb; ++b) {
    const SparseGrid::Coord c = grid.coord(b);
    const std::uint64_t k = SparseGrid::key(c.x, c.y, c.z);
    const int owner = decomp.rank_of(k);
    halo.owned[b] = owner == me ? 1 : 0;
    // Owner blocks b - s (s in {0,1}^3) are the only ones whose stencils reach b.
    // Blocks near a symmetry or fixed plane always go through their owner, who mirrors them.
    bool remote = owner != me || decomp.near_plane(k);
    std::int32_t slot[SparseGrid::kColours];
    std::fill(std::begin(slot), std::end(slot), -1);
    for (int sft = 0; sft < 8; ++sft) {
      const std::int64_t o[3] = {std::int64_t{c.x} - (sft & 1),
                                 std::int64_t{c.y} - ((sft >> 1) & 1),
                                 std::int64_t{c.z} - ((sft >> 2) & 1)};
      const std::uint64_t ok = SparseGrid::key(o[0], o[1], o[2]);
      if (decomp.rank_of(ok) != me) {
        remote = true;
        continue;
      }
      const std::int64_t ob = grid.find(ok);
      if (ob < 0 || grid.owned(static_cast<std::uint32_t>(ob)).empty()) continue;
      const int colour = static_cast<int>((o[0] & 1) | ((o[1] & 1) << 1) | ((o[2] & 1) << 2));
      slot[colour] = 1;
    }
    if (!remote) continue;
    const auto h = static_cast<std::uint32_t>(halo.blocks.size());
    halo.blocks.push_back(b);
    halo.owner.push_back(owner);
    if (owner != me) ++halo.ghosts_to[static_cast<std::size_t>(owner)];
    for (int col = 0; col < SparseGrid::kColours; ++col) {
      halo.slot.push_back(slot[col] >= 0 ? slots++ : -1);
      if (slot[col] >= 0) halo.by_colour[static_cast<std::size_t>(col)].push_back(h);
    }
  }
  halo.slots.resize(static_cast<std::size_t>(slots) * kForceFields * SparseGrid::kBlockNodes);
}

bool Simulation::Impl::decomp_planes_empty() const {
  for (const auto& pl : boundaries.planes()) {
    if (pl.kind == BoundaryKind::symmetry || pl.kind == BoundaryKind::fixed) return false;
  }
  return true;
}

void Simulation::Impl::halo_zero(int colour, int fields) {
  const auto F = node_fields(grid.nodes());
  for (const std::uint32_t h : halo.by_colour[static_cast<std::size_t>(colour)]) {
    const std::size_t at = std::size_t{halo.blocks[h]} * SparseGrid::kBlockNodes;
    // the mass of a momentum-only scatter is step 1's and stays
    for (int f = fields == kForceFields ? 0 : 1; f < (fields == kForceFields ? 7 : 4); ++f) {
      std::fill_n(F[static_cast<std::size_t>(f)]->begin() + static_cast<std::ptrdiff_t>(at),
                  SparseGrid::kBlockNodes, 0.0);
    }
  }
}

void Simulation::Impl::halo_capture(int colour, int fields) {
  const auto F = node_fields(grid.nodes());
  constexpr int BN = SparseGrid::kBlockNodes;
  for (const std::uint32_t h : halo.by_colour[static_cast<std::size_t>(colour)]) {
    const std::size_t at = std::size_t{halo.blocks[h]} * BN;
    const auto slot = static_cast<std::size_t>(halo.slot[h * 8 + static_cast<std::size_t>(colour)]);
    double* out = halo.slots.data() + slot * kForceFields * BN;
    for (int f = fields == kForceFields ? 0 : 1; f < (fields == kForceFields ? 7 : 4); ++f) {
      std::copy_n(F[static_cast<std::size_t>(f)]->begin() + static_cast<std::ptrdiff_t>(at), BN,
                  out + f * BN);
    }
  }
}

// Partial sums of halo blocks to their owner, which forms each node's sum from the partials of
// every colour in colour order, starting from zero, as the single process does (SparseGrid:
// every node gets at most one partial per colour), then sends the sums back to the ranks that
// sent partials. Messages are aggregated per neighbour rank: one each way per pair and call.
void Simulation::Impl::halo_reduce(int fields) {
  constexpr int BN = SparseGrid::kBlockNodes;
  const int f0 = fields == kForceFields ? 0 : 1, f1 = fields == kForceFields ? 7 : 4;
  const std::size_t width = static_cast<std::size_t>(f1 - f0) * BN;  // doubles per block
  const auto F = node_fields(grid.nodes());
  const auto ranks = static_cast<std::size_t>(comm.size());
  const auto me = comm.rank();
  // 1. partials of ghost blocks, by owner rank: key, colour mask, one block of values per colour
  std::vector<parallel::Bytes> send(ranks);
  for (std::size_t h = 0; h < halo.blocks.size(); ++h) {
    if (halo.owner[h] == me) continue;
    auto& out = send[static_cast<std::size_t>(halo.owner[h])];
    const SparseGrid::Coord c = grid.coord(halo.blocks[h]);
    parallel::put(out, SparseGrid::key(c.x, c.y, c.z));
    std::uint64_t mask = 0;
    for (int col = 0; col < 8; ++col) {
      if (halo.slot[h * 8 + static_cast<std::size_t>(col)] >= 0) mask |= 1u << col;
    }
    parallel::put(out, mask);
    for (int col = 0; col < 8; ++col) {
      const std::int32_t sl = halo.slot[h * 8 + static_cast<std::size_t>(col)];
      if (sl < 0) continue;
      parallel::put(out,
                    halo.slots.data() + static_cast<std::size_t>(sl) * kForceFields * BN + f0 * BN,
                    width);
    }
  }
  const std::vector<parallel::Bytes> recv = comm.exchange(send, &halo_traffic);

  // 2. the owner's sums: local partials of owned halo blocks, and every received partial
  struct Target {
    std::int64_t block = -1;  // local block, or -1: a block only other ranks' particles reach
    std::size_t temp = 0;
    std::array<const double*, 8> src{};
  };
  std::vector<Target> targets;
  std::unordered_map<std::uint64_t, std::size_t> index;
  std::vector<double> temp;
  for (std::size_t h = 0; h < halo.blocks.size(); ++h) {
    if (halo.owner[h] != me) continue;
    Target t;
    t.block = halo.blocks[h];
    for (int col = 0; col < 8; ++col) {
      const std::int32_t sl = halo.slot[h * 8 + static_cast<std::size_t>(col)];
      if (sl >= 0)
        t.src[static_cast<std::size_t>(col)] =
            halo.slots.data() + static_cast<std::size_t>(sl) * kForceFields * BN + f0 * BN;
    }
    const SparseGrid::Coord c = grid.coord(halo.blocks[h]);
    index.emplace(SparseGrid::key(c.x, c.y, c.z), targets.size());
    targets.push_back(t);
  }
  std::vector<std::vector<std::size_t>> reply(ranks);
  for (std::size_t q = 0; q < ranks; ++q) {
    if (static_cast<int>(q) == me) continue;
    const parallel::Bytes& b = recv[q];
    std::size_t at = 0;
    while (at < b.size()) {
      std::uint64_t k = 0, mask = 0;
      std::memcpy(&k, b.data() + at, 8);
      std::memcpy(&mask, b.data() + at + 8, 8);
      at += 16;
      auto [it, fresh] = index.emplace(k, targets.size());
      if (fresh) {
        Target t;
        const std::int64_t lb = grid.find(k);
        if (lb >= 0) {
          throw std::logic_error("halo: partials for an owned block outside the halo plan");
        }
        t.temp = temp.size();
        temp.resize(temp.size() + width);
        targets.push_back(t);
      }
      Target& t = targets[it->second];
      for (int col = 0; col < 8; ++col) {
        if (!(mask >> col & 1)) continue;
        if (t.src[static_cast<std::size_t>(col)] != nullptr) {
          throw std::logic_error("halo: two partials of one colour for one block");
        }
        t.src[static_cast<std::size_t>(col)] = reinterpret_cast<const double*>(b.data() + at);
        at += width * sizeof(double);
      }
      reply[q].push_back(it->second);
    }
  }
  // recv buffers hold doubles at 16-byte + k*width offsets: aligned for double reads, since
  // std::vector<std::byte> storage comes from operator new (16-byte aligned).
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, targets.size(), 16),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t t = r.begin(); t < r.end(); ++t) {
                        const Target& tg = targets[t];
                        for (int f = f0; f < f1; ++f) {
                          double* out = tg.block >= 0 ? F[static_cast<std::size_t>(f)]->data() +
                                                            static_cast<std::size_t>(tg.block) * BN
                                                      : temp.data() + tg.temp +
                                                            static_cast<std::size_t>(f - f0) * BN;
                          const std::size_t off = static_cast<std::size_t>(f - f0) * BN;
                          for (int l = 0; l < BN; ++l) {
                            double v = 0.0;
                            for (int col = 0; col < 8; ++col) {
                              const double* src = tg.src[static_cast<std::size_t>(col)];
                              if (src != nullptr) v += src[off + static_cast<std::size_t>(l)];
                            }
                            out[l] = v;
                          }
                        }
                      }
                    });
  // The unresolved kinetic energy's node sum (unresolved_kinetic()) on several ranks: every node
  // by its owner, from the complete sums before 2b mirrors them, as one process sums its nodes
  // before its mirror. Owned blocks outside the halo are complete after the scatter (no other
  // rank reaches them, none is near a plane); owned halo blocks are the targets, local or not.
  if (fields == kForceFields) {
    std::vector<std::uint8_t> target(grid.blocks(), 0);
    for (const Target& tg : targets) {
      if (tg.block >= 0) target[static_cast<std::size_t>(tg.block)] = 1;
    }
    parallel::ExactSum acc = node_unresolved(
        grid.blocks(), [&](std::uint32_t b) { return halo.owned[b] != 0 && target[b] == 0; },
        [&](std::uint32_t b, int f) {
          return F[static_cast<std::size_t>(f)]->data() + std::size_t{b} * BN;
        });
    for (const Target& tg : targets) {
      const double* v[4];
      for (int f = 0; f < 4; ++f) {
        v[f] = tg.block >= 0 ? F[static_cast<std::size_t>(f)]->data() +
                                   static_cast<std::size_t>(tg.block) * BN
                             : temp.data() + tg.temp + static_cast<std::size_t>(f) * BN;
      }
      add_node_unresolved(v, acc);
    }
    unresolved_sum = acc;
  }
  // 2b. symmetry and fixed planes, on the owner's complete sums (every block near a plane is a
  // halo block, and a ghost and its partner have one owner: Decomposition::set_planes)
  if (!decomp_planes_empty()) {
    struct Blocks {
      Impl& im;
      std::vector<Target>& t;
      std::unordered_map<std::uint64_t, std::size_t>& index;
      std::vector<double>& temp;
      int f0;
      std::vector<SparseGrid::Coord> coords;
      std::size_t size() const { return t.size(); }
      SparseGrid::Coord coord(std::size_t i) const { return coords[i]; }
      std::int64_t find(std::uint64_t k) const {
        const auto it = index.find(k);
        return it == index.end() ? -1 : static_cast<std::int64_t>(it->second);
      }
      double* field(std::size_t i, int f) {
        const Target& tg = t[i];
        if (tg.block >= 0) {
          return node_fields(im.grid.nodes())[static_cast<std::size_t>(f)]->data() +
                 static_cast<std::size_t>(tg.block) * SparseGrid::kBlockNodes;
        }
        return temp.data() + tg.temp + static_cast<std::size_t>(f - f0) * SparseGrid::kBlockNodes;
      }
    } blocks{*this, targets, index, temp, f0, {}};
    blocks.coords.resize(targets.size());
    for (const auto& [k, i] : index) blocks.coords[i] = decode_key(k);
    boundaries.mirror_blocks(blocks, fields == kForceFields ? mpm::Boundaries::kMassMomentumForce
                                                            : mpm::Boundaries::kMomentum);
  }
  // 3. the sums back to the ranks that sent partials, in the order they sent them
  std::vector<parallel::Bytes> back(ranks), back_in(ranks);
  for (std::size_t q = 0; q < ranks; ++q) {
    for (const std::size_t t : reply[q]) {
      const Target& tg = targets[t];
      for (int f = f0; f < f1; ++f) {
        const double* v =
            tg.block >= 0
                ? F[static_cast<std::size_t>(f)]->data() + static_cast<std::size_t>(tg.block) * BN
                : temp.data() + tg.temp + static_cast<std::size_t>(f - f0) * BN;
        parallel::put(back[q], v, BN);
      }
    }
    back_in[q].resize(halo.ghosts_to[q] * width * sizeof(double));
  }
  comm.exchange_known(back, back_in, &halo_traffic);
  std::vector<std::size_t> read(ranks, 0);
  for (std::size_t h = 0; h < halo.blocks.size(); ++h) {
    if (halo.owner[h] == me) continue;
    const auto q = static_cast<std::size_t>(halo.owner[h]);
    const std::byte* src = back_in[q].data() + read[q];
    read[q] += width * sizeof(double);
    const std::size_t at = std::size_t{halo.blocks[h]} * BN;
    for (int f = f0; f < f1; ++f) {
      std::memcpy(F[static_cast<std::size_t>(f)]->data() + at,
                  src + static_cast<std::size_t>(f - f0) * BN * sizeof(double),
                  BN * sizeof(double));
    }
  }
}

}  // namespace shatter
