// App. A.2 step 5a, filtered transfers: XPIC(m) (Hammerquist & Nairn 2017) and FMPM(k) (Nairn
// & Hammerquist 2021; Nairn 2026), the extra grid-particle-grid passes of their series.

#include <string>

#include "mpm/loops.hpp"
#include "mpm/stages/stages.hpp"
#include "mpm/state.hpp"
#include "parallel/mpm/exchanges.hpp"
#include "shatter/mpm/kernel_inputs.hpp"

namespace shatter::mpm {
namespace {

// Sets v^{n+1} aside in filter.v and sizes the passes' arrays.
void series_arrays(State& s, bool with_target) {
  auto& N = s.grid.nodes();
  std::vector<double>* mom[3] = {&N.px, &N.py, &N.pz};
  const std::size_t nodes = N.px.size();
  FilterArrays& f = s.filter;
  for (int d = 0; d < 3; ++d) {
    f.v[d].swap(*mom[d]);  // v^{n+1} aside; the momentum arrays become the passes' workspace
    mom[d]->resize(nodes);
    f.term[d].resize(nodes);
    if (with_target) f.target[d].resize(nodes);
    f.w[d].resize(s.particles.size());
  }
}

// The extra grid-particle-grid passes of XPIC and FMPM, shared: passes 2..terms of the series
// in A = M_L^{-1} M_c = S+ S, each two stages (add_filter_stages) with the exchange of the node
// sums between them on several ranks. Before pass 2, v^{n+1} (after grid_update's boundary
// conditions) is set aside in filter.v (series_arrays), the momentum arrays become the passes'
// workspace and the caller fills filter.term with the first pass's input. One pass is the
// gather S of filter.term to the points (kernels::gather_velocity, from the stencils of this
// step) and the momentum-only scatter of the MUSL remap (same colouring, so node sums keep their
// canonical order) (scatter_pass), then the remap's boundary conditions (mirror, wall
// velocities): S+ includes them, as in both papers (boundary_pass); the series' update then
// reads (A filter.term)_i from the momentum arrays and writes the next pass's input into
// filter.term. After the last pass the caller swaps the arrays back.
template <class Shape>
void scatter_pass(State& s) {
  ParticleStore& P = s.particles;
  SparseGrid& grid = s.grid;
  kernels::G2PParticles in = g2p_inputs(P, s.inv_h(), nullptr, nullptr, nullptr);
  in.stencil = s.stencil_rows<Shape>();
  FilterArrays& f = s.filter;
  double* w[3] = {f.w[0].data(), f.w[1].data(), f.w[2].data()};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, P.size(), kParticleGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t p = r.begin(); p < r.end(); ++p) {
                        kernels::gather_velocity<Shape>(
                            in, p, grid.coord(grid.owner_of(p)), grid.particle_neighbours(p),
                            f.term[0].data(), f.term[1].data(), f.term[2].data(), w[0], w[1], w[2]);
                      }
                    });
  p2g<Shape>(s, false, w);
}

void boundary_pass(State& s) {
  if (!s.dist()) s.boundaries.mirror(s.grid, Boundaries::kMomentum);
  s.boundaries.velocities(s.grid, s.empty_mass);
}

// XPIC(m), Hammerquist & Nairn (2017): V*_m = sum_{k=1..m} (-1)^{k+1} C(m,k) (S+ S)^{k-1} V^L,
// with V^L = S+ v_p the lumped grid velocity of the particles at the start of the step and
// (S+ S V)_I = (1/m_I) sum_p m_p N_I(x_p) sum_J N_J(x_p) V_J one grid-particle-grid pass. It is
// the grid form of their particle update v_p <- v_p - (I - S S+)^m v_p + S a dt: the PIC
// filter's projection I - S S+ applied m times, so velocity noise in the null space of S+ is
// removed while what the grid can represent loses only its (I - S+ S)^m part. The term C(m,k)
// (S+S)^{k-1} V^L is formed recursively with the ratio C(m,k)/C(m,k-1) = (m-k+1)/k, as in the
// authors' own code (NairnMPM, XPICExtrapolationTask). G2P then takes S (V*_m + a dt) =
// S (v^{n+1} + V*_m - V^L), which is v^{n+1} itself, and so PIC bitwise, for m = 1.
// Before pass 2: k = 1, C(m,1) V^L, with V^L = v^{n+1} - a dt (the lumped velocity after the
// boundary conditions of grid_update). filter.target accumulates V*_m - V^L.
void xpic_begin(State& s) {
  auto& N = s.grid.nodes();
  const int m = s.transfer.order;
  const double dt = 0.5 * (s.clock.dt_prev + s.dt_step);  // the kick of grid_update
  const std::vector<double>* acc[3] = {&N.fx, &N.fy, &N.fz};
  FilterArrays& f = s.filter;
  series_arrays(s, true);
  const double md = static_cast<double>(m);
  node_loop(N.px.size(), [&](std::size_t i) {
    for (int d = 0; d < 3; ++d) {
      const double vl = f.v[d][i] - dt * (*acc[d])[i];
      f.term[d][i] = md * vl;
      f.target[d][i] = (md - 1.0) * vl;
    }
  });
}

// After pass k: term k of the series, C(m,k)/C(m,k-1) = (m-k+1)/k times the pass's result.
void xpic_update(State& s, int k) {
  auto& N = s.grid.nodes();
  const int m = s.transfer.order;
  std::vector<double>* mom[3] = {&N.px, &N.py, &N.pz};
  FilterArrays& f = s.filter;
  node_loop(N.px.size(), [&](std::size_t i) {
    const double ratio = static_cast<double>(m - k + 1) / static_cast<double>(k);
    const double sign = k % 2 == 0 ? -1.0 : 1.0;  // (-1)^{k+1}
    for (int d = 0; d < 3; ++d) {
      const double t = ratio * (*mom[d])[i];
      f.term[d][i] = t;
      f.target[d][i] += sign * t;
    }
  });
}

// After the last pass: V*_m + a dt = v^{n+1} + (V*_m - V^L) for G2P.
void xpic_end(State& s) {
  auto& N = s.grid.nodes();
  std::vector<double>* mom[3] = {&N.px, &N.py, &N.pz};
  FilterArrays& f = s.filter;
  node_loop(N.px.size(), [&](std::size_t i) {
    for (int d = 0; d < 3; ++d) f.target[d][i] += f.v[d][i];
  });
  for (int d = 0; d < 3; ++d) f.v[d].swap(*mom[d]);  // v^{n+1} back for the displacement
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
// Before pass 2: v^(1) = M_L^{-1} p^{n+1}.
void fmpm_begin(State& s) {
  FilterArrays& f = s.filter;
  series_arrays(s, false);
  node_loop(s.grid.nodes().px.size(), [&](std::size_t i) {
    for (int d = 0; d < 3; ++d) f.term[d][i] = f.v[d][i];
  });
}

// After each pass: v^(j) = v^(1) + (I - A) v^(j-1).
void fmpm_update(State& s, int /*k: every pass alike*/) {
  auto& N = s.grid.nodes();
  std::vector<double>* mom[3] = {&N.px, &N.py, &N.pz};
  FilterArrays& f = s.filter;
  node_loop(N.px.size(), [&](std::size_t i) {
    for (int d = 0; d < 3; ++d) {
      f.term[d][i] = f.v[d][i] + (f.term[d][i] - (*mom[d])[i]);  // v1 + (I - A) v
    }
  });
}

// After the last pass: v_F where G2P reads v^{n+1}.
void fmpm_end(State& s) {
  auto& N = s.grid.nodes();
  std::vector<double>* mom[3] = {&N.px, &N.py, &N.pz};
  for (int d = 0; d < 3; ++d) s.filter.term[d].swap(*mom[d]);
}

// What the filter reads and writes. Its stages (each pass's scatter, exchange and nodal update)
// each declare all of it, so every other stage is ordered against each of them as against the
// filter as a whole.
constexpr Access kFilterReads{kGeometry | FieldSet{Field::mass}, kBlocks | kClock};
constexpr Access kFilterWrites{{}, kGrid};

}  // namespace

// Pass k (2..m) of the series is two stages, the scatter ("xpic" or "fmpm") and the nodal
// update ("xpic_nodes", "fmpm_nodes"), with the exchange of the scatter's node sums between them
// on several ranks ("halo_xpic", "halo_fmpm"): the exchanges are stages of their own. The first
// scatter sets up the series, the last nodal update ends it; every stage does nothing on the
// steps filter_every leaves unfiltered (State::filtering, the same on every rank).
template <class Shape>
void add_filter_stages(State& s) {
  const bool is_xpic = s.transfer.kind == TransferKind::xpic;
  const int m = s.transfer.order;
  const std::string name = s.transfer.filter_name();
  for (int k = 2; k <= m; ++k) {
    const Stage scatter{name, kFilterReads, kFilterWrites, [&s, is_xpic, k] {
                          if (!s.filtering) return;
                          if (k == 2) (is_xpic ? xpic_begin : fmpm_begin)(s);
                          scatter_pass<Shape>(s);
                        }};
    s.graph.add(scatter);
    if (s.dist()) s.graph.add(parallel::momentum_halo_stage(s, scatter, true));
    s.graph.add({name + "_nodes", kFilterReads, kFilterWrites, [&s, is_xpic, k, m] {
                   if (!s.filtering) return;
                   boundary_pass(s);
                   (is_xpic ? xpic_update : fmpm_update)(s, k);
                   if (k == m) (is_xpic ? xpic_end : fmpm_end)(s);
                 }});
  }
}

#define SHATTER_INSTANTIATE(S) template void add_filter_stages<S>(State & s);
SHATTER_FOR_EACH_SHAPE(SHATTER_INSTANTIATE)

}  // namespace shatter::mpm
