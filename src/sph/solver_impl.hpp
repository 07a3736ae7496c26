#pragma once
// The SPH solver's working state and its parts (private to src/sph). The step of
// include/shatter/sph/solver.hpp is carried out by the parts, one file each:
//
//   mirrors.cpp    the mirror particles of the symmetry and slip faces, and the faces' effect on
//                  the drift (reflection back, outflow)
//   lists.cpp      smoothing lengths, the Verlet neighbour lists, the memory re-order (steps 5-6)
//   passes.cpp     kick, the rates and forces gather passes, material update, drift (steps 1-4, 6)
//   switch.cpp     the Morris & Monaghan viscosity switch's alpha per particle
//   time_step.cpp  the energies at t^{n+1}, the next dt and the finite-state check (step 7)
//   setup.cpp      the checks of the configuration and the store, and the first forces
//   solver.cpp     the step itself, restore and the public accessors

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

#include "shatter/gravity/self_gravity.hpp"
#include "shatter/sph/solver.hpp"
#include "sph/gather.hpp"
#include "sph/weight_buffer.hpp"

namespace shatter::sph {

namespace ks = kernels::sph;

// Fixed grain sizes (never derived from the thread count): reductions split the same way on any
// number of threads, so their sums have the same bits.
inline constexpr std::size_t kGrain = 2048;
inline constexpr std::size_t kPairGrain = 256;

// Groups of the SIMD width in a list of `count` pairs: the bytes of its viscous weights' mask.
inline std::size_t groups(std::size_t count) {
  constexpr std::size_t W = kernels::sph::Lanes<simd::Batch>::width;
  return (count + W - 1) / W;
}

template <class F>
double deterministic_sum(std::size_t n, F&& term) {
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<std::size_t>(0, n, kGrain), 0.0,
      [&](const tbb::blocked_range<std::size_t>& r, double acc) {
        for (std::size_t p = r.begin(); p < r.end(); ++p) acc += term(p);
        return acc;
      },
      std::plus<>());
}

template <class F>
double exact_max(std::size_t n, F&& term) {
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, n, kGrain), 0.0,
      [&](const tbb::blocked_range<std::size_t>& r, double acc) {
        for (std::size_t p = r.begin(); p < r.end(); ++p) acc = std::max(acc, term(p));
        return acc;
      },
      [](double a, double b) { return std::max(a, b); });
}

template <class F>
double exact_min(std::size_t n, double init, F&& term) {
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, n, kGrain), init,
      [&](const tbb::blocked_range<std::size_t>& r, double acc) {
        for (std::size_t p = r.begin(); p < r.end(); ++p) acc = std::min(acc, term(p));
        return acc;
      },
      [](double a, double b) { return std::min(a, b); });
}

inline constexpr Field kStressOrder[6] = {Field::sxx, Field::syy, Field::szz,
                                          Field::sxy, Field::syz, Field::sxz};
inline constexpr Field kDepsOrder[6] = {Field::deps_xx, Field::deps_yy, Field::deps_zz,
                                        Field::deps_xy, Field::deps_yz, Field::deps_xz};
inline constexpr Field kSpinOrder[3] = {Field::dspin_xy, Field::dspin_yz, Field::dspin_xz};

enum Stage : std::size_t { kKick, kRates, kMaterial, kDrift, kSearch, kForces, kEnergy, kStages };

// The kinetic energy of the store at its current velocities (deterministic sum).
double kinetic_energy(const ParticleStore& P);

// A mirror particle (ghost) of the boundaries: the image of real particle `src` across the planes
// of the axes whose side is not 0 (-1: the lower face, +1: the upper face; several for an edge
// or corner image). It carries the source's mass, density, h and sound speed, its position and
// velocity reflected, and its stress with the shear components that have one reflected index
// negated: the state of the mirror-image body, so that a half model gathers exactly the sums of
// the symmetric full model (Libersky et al. 1993, J. Comput. Phys. 109, 67, Sec. 3.3, for SPH
// solids; Monaghan 1994 uses the same images for free-slip walls).
struct Mirror {
  std::uint32_t src;
  std::array<std::int8_t, 3> side;
};

struct SphSolver::Impl {
  SphSolver& s;
  tbb::task_arena arena;
  NeighbourSearch search;
  // Real particles 0 .. n-1, then mirror particles n .. n+g-1 (h, h_mid, ax, ay, az, a_stress
  // and the e* copies have n + g entries; heat n). `heat` is written by the forces pass and read
  // by energy() at the end of the same step; between those it is free, and holds the kick's
  // viscous heat in the rates pass and serves as the re-order's scratch column. h_mid lives from
  // the rates pass's start (midpoint_smoothing_lengths) to the material update's end
  // (evolve_switch), and is the search's reach in a build; from the forces pass to next_dt() it
  // holds max_j |mu_ij| of each real particle (`mu` had its own column: 8 B per point).
  AlignedVector<double> h, h_mid, ax, ay, az, heat;
  // Boundaries (DESIGN.md "The SPH step", boundaries): faces that reflect (symmetry, slip) and
  // faces that let particles out (outflow).
  std::array<bool, 6> mirror_face{}, outflow_face{};
  bool mirrors = false, outflows = false;
  std::vector<Mirror> ghosts;
  std::vector<std::uint8_t> leaving;
  // With mirror particles the gather passes read these copies of the columns (real particles,
  // then their images); without, they read the columns themselves.
  AlignedVector<double> ex, ey, ez, evx, evy, evz, em, erho, ec;
  // The pairs within support at the last forces pass: the first active_count[i] entries of i's
  // Verlet list, in ascending order (compact_lists re-arranges each list in place); whether the
  // lists are as a build or permute left them (ascending throughout); scratch per thread for the
  // re-arrangement.
  std::vector<std::uint32_t> active_count;
  bool lists_sorted = false;
  tbb::enumerable_thread_specific<std::vector<std::uint32_t>> rest;
  // The pairs' viscous weights (viscous_heating_term), per chunk of kPairGrain particles (the
  // passes run over whole chunks): only the non-zero ones, a chunk's in particle and list order
  // from pair_w[chunk_w[c]] on (chunk_w_count[c] of them, in a room of chunk_room[c]), and a
  // byte per group of the SIMD width of list entries saying which are there, a chunk's from
  // pair_mask[chunk_mask[c]] on. A chunk that outgrows its room moves its weights to a
  // per-thread buffer (`packing`) and keeps them in `spill` until the pass has ended, when
  // pair_w is laid out anew, in place (place_weights).
  std::vector<std::size_t> chunk_w, chunk_room, chunk_w_count, chunk_mask;
  WeightBuffer pair_w;
  std::vector<std::uint8_t> pair_mask;
  tbb::enumerable_thread_specific<std::vector<double>> packing;
  std::vector<std::vector<double>> spill;
  std::array<AlignedVector<double>, 6> a_stress;  // sigma / rho^2
  // The Morris & Monaghan switch: alpha per particle (state: follows the particles through the
  // re-order and the outflow; real then mirror entries). The normalized continuity: a copy of
  // rho^n for the rates pass.
  bool switch_on = false;
  ks::SwitchCoefficients switch_k;
  AlignedVector<double> alpha, rho_n;
  std::vector<std::uint32_t> order;
  std::vector<StageTiming> timings;
  std::unique_ptr<gravity::SelfGravity> gravity;  // gravity.self only (sph/gravity.cpp)
  // Verlet lists: positions, h and half skins s_p at the last build (particle_skins), the
  // largest pair skin 2 max s_p (m), whether the lists are those of the current store (false
  // after a restore or when particles left), and the number of builds. In single precision
  // (20 B per point instead of 40): the skins and h rounded down (a build uses the rounded
  // skins themselves), the positions to nearest, their rounding bounded in lists_still_cover.
  std::vector<float> xb, yb, zb, hb, skin;
  double skin_abs = 0.0;
  bool lists_valid = false;
  std::uint64_t builds = 0;
  // The re-order's carry of the lists through the permutation (permute_lists): the last
  // build's images, and each point's new index (real particles, then images).
  std::vector<Mirror> kept_ghosts;
  std::vector<std::uint32_t> renumber;

  Impl(SphSolver& solver, int threads);

  template <class F>
  void timed(Stage stage, F&& f) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    timings[stage].seconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }

  // mirrors.cpp
  double plane(std::size_t face) const;
  void make_ghosts(double hmax);
  void size_ghost_columns(std::size_t m);
  void place_ghosts();
  void mirror_vector(double* vx, double* vy, double* vz, std::size_t n) const;
  void mirror_scalar(double* v, std::size_t n) const;
  void refresh_ghost_state();
  void mirror_stress(std::size_t n);
  void reflect_after_drift();
  void outflow_after_drift();
  ks::PairInputs inputs();

  // lists.cpp
  void resize(std::size_t n);
  void smoothing_lengths();
  double particle_skins(double hmax, bool with_skin);
  void lend_weights(std::size_t points);
  void build_search(bool with_skin = true, bool lists = true);
  bool lists_still_cover() const;
  void reorder_by_cell(bool keep_lists);
  void permute_lists();
  void search_and_forces(bool may_reorder);

  // passes.cpp
  void kick(double dt_kick);
  void constrain_velocities(double t_half);
  void heat_from_kick();
  void midpoint_smoothing_lengths(double dt);
  void rates(double dt, double dt_kick);
  void material(double dt);
  void drift(double dt);
  void compact_lists(const ks::PairInputs& in);
  void place_weights();
  bool forces_chunk(std::size_t c, const ks::PairInputs& in, const ks::ForceInputs& f);
  void forces();
  void add_self_gravity();  // a += the particles' self-gravity (sph/gravity.cpp)

  // switch.cpp
  void start_switch();
  void evolve_switch(double dt);
  void permute_switch();
  void drop_leaving_switch(std::size_t n);

  // time_step.cpp
  void energy();
  double stable_dt() const;
  void next_dt();
  void check_state() const;
};

}  // namespace shatter::sph
