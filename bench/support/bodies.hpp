#pragma once
// Shared set-up for the stage benchmarks (header-only: bench/CMakeLists.txt makes a program from
// every bench/*.cpp). A body is a box lattice of material points, 2x2x2 per grid cell (8 per
// cell, the MPM paper's set-up), of a stiff elastic solid in smooth non-uniform motion, so that
// every stage has real work (non-zero stress, strain and spin).

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <initializer_list>
#include <numeric>
#include <span>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "mpm/shape.hpp"
#include "shatter/core/config.hpp"
#include "shatter/core/particles.hpp"
#include "shatter/grid/sparse_grid.hpp"

namespace shatter::bench {

inline constexpr double kCell = 0.01;            // h [m]
inline constexpr double kSpacing = 0.5 * kCell;  // 2 points per cell and axis
inline constexpr double kRho = 2700.0, kYoung = 7.0e10, kPoisson = 0.3;  // aluminium-like

// Particle counts of the two sizes; lattices chosen to hit them exactly.
struct Lattice {
  int nx, ny, nz;
  std::size_t size() const {
    return static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny) *
           static_cast<std::size_t>(nz);
  }
};
inline Lattice lattice_for(std::int64_t n) {
  if (n == 100'000) return {50, 50, 40};
  if (n == 1'000'000) return {100, 100, 100};
  const int e = static_cast<int>(std::lround(std::cbrt(static_cast<double>(n))));
  return {e, e, e};
}

// The engine's own columns (as Simulation registers them) plus what the scene supplies. The
// strain and spin increments are not among them (issue 35: the step keeps them per chunk); a
// benchmark of one kernel that reads them from the store registers them itself.
inline constexpr FieldSet kEngineColumns =
    kPosition | kVelocity | kStress | FieldSet{Field::mass,      Field::volume0, Field::size0,
                                               Field::rho,       Field::energy,  Field::pressure,
                                               Field::soundspeed};

// A box of n (see lattice_for) points in one group (material 0), lattice (i, j, k) order.
// Velocity: a uniform drift along x plus smooth shear and compression waves of ~10 m/s; stress: a
// smooth field of ~10 MPa.
inline ParticleStore make_body(std::int64_t n, double drift = 5.0) {
  const Lattice L = lattice_for(n);
  ParticleStore s;
  s.require(kEngineColumns);
  s.require(IField::id);
  const Range r = s.add_group(0, L.size());
  const double two_pi = 2.0 * M_PI;
  const double len = kSpacing * L.nx;
  // Origin off the block grid so stencils straddle blocks as in a real scene.
  const double o[3] = {0.0123, -0.0371, 0.0057};
  std::size_t p = r.begin;
  auto col = [&](Field f) { return s.col(f).data(); };
  double *x = col(Field::x), *y = col(Field::y), *z = col(Field::z);
  double *vx = col(Field::vx), *vy = col(Field::vy), *vz = col(Field::vz);
  double *sxx = col(Field::sxx), *syy = col(Field::syy), *sxy = col(Field::sxy);
  for (int i = 0; i < L.nx; ++i) {
    for (int j = 0; j < L.ny; ++j) {
      for (int k = 0; k < L.nz; ++k, ++p) {
        x[p] = o[0] + kSpacing * (i + 0.5);
        y[p] = o[1] + kSpacing * (j + 0.5);
        z[p] = o[2] + kSpacing * (k + 0.5);
        const double a = two_pi * x[p] / len, b = two_pi * y[p] / len, c = two_pi * z[p] / len;
        vx[p] = drift + 10.0 * std::sin(b);
        vy[p] = 8.0 * std::sin(c);
        vz[p] = -6.0 * std::sin(a);
        sxx[p] = 1e7 * std::cos(a);
        syy[p] = -5e6 * std::cos(b);
        sxy[p] = 2e6 * std::sin(c);
        s.col(IField::id)[p] = static_cast<std::int64_t>(p);
      }
    }
  }
  const double vol = kSpacing * kSpacing * kSpacing;
  for (std::size_t q = r.begin; q < r.end; ++q) {
    s.col(Field::mass)[q] = kRho * vol;
    s.col(Field::volume0)[q] = vol;
    s.col(Field::size0)[q] = kSpacing;
    s.col(Field::rho)[q] = kRho;
    s.col(Field::soundspeed)[q] = 6000.0;
  }
  return s;
}

// Owner-block key of every particle, exactly as the engine's sort stage computes it.
template <class Shape>
void owner_keys(const ParticleStore& s, std::vector<std::uint64_t>& keys) {
  const std::size_t n = s.size();
  keys.resize(n);
  const double ih = 1.0 / kCell;
  const double shift = Shape::kWidth == 3 ? 0.5 : 0.0;
  const double* X[3] = {s.col(Field::x).data(), s.col(Field::y).data(), s.col(Field::z).data()};
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, n, 2048), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t p = r.begin(); p < r.end(); ++p) {
          std::int64_t b[3];
          for (int d = 0; d < 3; ++d) {
            const double xi = X[d][p] * ih - shift;
            b[d] = static_cast<std::int64_t>(std::floor(xi)) >> SparseGrid::kBlockBits;
          }
          keys[p] = SparseGrid::key(b[0], b[1], b[2]);
        }
      });
}

// Physically re-orders the store by owner block (stable), as the sort stage does every
// reorder_interval steps; returns the keys in the new order.
template <class Shape>
std::vector<std::uint64_t> sort_by_block(ParticleStore& s) {
  std::vector<std::uint64_t> keys;
  owner_keys<Shape>(s, keys);
  std::vector<std::uint32_t> order(s.size());
  std::iota(order.begin(), order.end(), 0U);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return keys[a] < keys[b]; });
  s.permute(order);
  std::vector<std::uint64_t> sorted(s.size());
  for (std::size_t k = 0; k < s.size(); ++k) sorted[k] = keys[order[k]];
  return sorted;
}

// Bytes of particle columns per particle (every registered column, double and integer).
inline double column_bytes_per_particle(const ParticleStore& s) {
  std::size_t cols = 0;
  for (std::size_t f = 0; f < kFieldCount; ++f) cols += s.has(static_cast<Field>(f)) ? 1 : 0;
  for (std::size_t f = 0; f < kIFieldCount; ++f) cols += s.has(static_cast<IField>(f)) ? 1 : 0;
  return 8.0 * static_cast<double>(cols);
}

// Common counters: particle-steps per second (items) and the memory footprint per particle.
inline void report(benchmark::State& state, const ParticleStore& s, std::size_t grid_bytes) {
  const auto n = static_cast<std::int64_t>(s.size());
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * n);
  state.counters["bytes/particle"] =
      column_bytes_per_particle(s) + static_cast<double>(grid_bytes) / static_cast<double>(n);
}

// Particle counts to run: `sizes`, or, when the environment sets SHATTER_BENCH_PARTICLES (a
// count, as the CI smoke run does with a tiny one), that count alone.
inline std::vector<std::int64_t> particle_counts(std::initializer_list<std::int64_t> sizes) {
  if (const char* e = std::getenv("SHATTER_BENCH_PARTICLES"); e != nullptr && *e != '\0') {
    const long long n = std::atoll(e);
    if (n > 0) return {static_cast<std::int64_t>(n)};
  }
  return sizes;
}

// Benchmark argument grid: particles {1e5, 1e6} x threads {1, 2}.
inline void sizes_and_threads(benchmark::internal::Benchmark* b) {
  b->ArgNames({"particles", "threads"});
  for (const std::int64_t n : particle_counts({100'000, 1'000'000})) {
    for (const std::int64_t t : {1, 2}) b->Args({n, t});
  }
  // Wall time drives items/s; CPU time is that of the whole process (all TBB threads), so that
  // items/CPU-second gives the per-core rate on a loaded machine.
  b->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime();
}

// 1e6 particles (or SHATTER_BENCH_PARTICLES) on 1 thread.
inline void one_thread(benchmark::internal::Benchmark* b) {
  b->ArgNames({"particles", "threads"});
  for (const std::int64_t n : particle_counts({1'000'000})) b->Args({n, 1});
}

}  // namespace shatter::bench
