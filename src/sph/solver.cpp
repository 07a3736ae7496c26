#include "shatter/sph/solver.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

#include "shatter/core/solver_inputs.hpp"
#include "sph/gather.hpp"

namespace shatter::sph {
namespace {

namespace ks = kernels::sph;

// Fixed grain sizes (never derived from the thread count): reductions split the same way on any
// number of threads, so their sums have the same bits.
constexpr std::size_t kGrain = 2048;
constexpr std::size_t kPairGrain = 256;

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

constexpr Field kStressOrder[6] = {Field::sxx, Field::syy, Field::szz,
                                   Field::sxy, Field::syz, Field::sxz};
constexpr Field kDepsOrder[6] = {Field::deps_xx, Field::deps_yy, Field::deps_zz,
                                 Field::deps_xy, Field::deps_yz, Field::deps_xz};
constexpr Field kSpinOrder[3] = {Field::dspin_xy, Field::dspin_yz, Field::dspin_xz};

const FieldSet kSphFields =
    kPosition | kVelocity | kStress | kStrainIncrement | kSpinIncrement |
    FieldSet{Field::mass, Field::rho, Field::energy, Field::pressure, Field::soundspeed};

enum Stage : std::size_t { kKick, kRates, kMaterial, kDrift, kSearch, kForces, kEnergy, kStages };

}  // namespace

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
  // and the e* copies have n + g entries; heat, mu and kick_heat n).
  AlignedVector<double> h, h_mid, ax, ay, az, heat, mu, kick_heat;
  // Boundaries (DESIGN.md "The SPH step", boundaries): faces that reflect (symmetry, slip) and
  // faces that let particles out (outflow).
  std::array<bool, 6> mirror_face{}, outflow_face{};
  bool mirrors = false, outflows = false;
  std::vector<Mirror> ghosts;
  std::vector<std::uint8_t> leaving;
  // With mirror particles the gather passes read these copies of the columns (real particles,
  // then their images); without, they read the columns themselves.
  AlignedVector<double> ex, ey, ez, evx, evy, evz, em, erho, ec;
  // Per neighbour-list entry: the pairs within support at the last forces pass, compacted to the
  // front of each list's slots (active_count[i] of them), and their viscous weights
  // (viscous_heating_term).
  std::vector<std::uint32_t> active, active_count;
  std::vector<double> pair_w;
  std::array<AlignedVector<double>, 6> a_stress;  // sigma / rho^2
  // The Morris & Monaghan switch: alpha per particle (state: follows the particles through the
  // re-order and the outflow; real then mirror entries). The normalized continuity: a copy of
  // rho^n for the rates pass.
  bool switch_on = false;
  ks::SwitchCoefficients switch_k;
  AlignedVector<double> alpha, rho_n;
  std::vector<std::uint32_t> order;
  std::vector<StageTiming> timings;
  // Verlet lists: positions and h at the last build, the skin it used (m), whether the lists
  // are those of the current store (false after a restore or when particles left), and the
  // number of builds.
  AlignedVector<double> xb, yb, zb, hb;
  double skin_abs = 0.0;
  bool lists_valid = false;
  std::uint64_t builds = 0;

  Impl(SphSolver& solver, int threads)
      : s(solver), arena(threads > 0 ? threads : tbb::task_arena::automatic) {
    for (const char* name : {"kick", "rates", "material", "drift", "search", "forces", "energy"}) {
      timings.push_back({name, 0.0});
    }
    for (std::size_t f = 0; f < 6; ++f) {
      const BoundaryKind k = s.config_.domain.faces[f];
      mirror_face[f] = k == BoundaryKind::symmetry || k == BoundaryKind::slip;
      outflow_face[f] = k == BoundaryKind::outflow;
      mirrors = mirrors || mirror_face[f];
      outflows = outflows || outflow_face[f];
    }
    switch_on = s.sph_.viscosity_switch == ViscositySwitch::morris_monaghan;
    switch_k = {s.sph_.alpha_min, s.sph_.alpha_max, s.sph_.switch_decay};
    // Every particle starts at alpha_max, the constant default's viscosity at the first contact
    // of an impact, and decays where nothing converges (in tau = h / (C c), a few sound
    // crossings of h).
    if (switch_on) alpha.assign(s.particles_.size(), s.sph_.alpha_max);
  }

  double plane(std::size_t face) const {
    return face % 2 == 0 ? s.config_.domain.lo[static_cast<int>(face / 2)]
                         : s.config_.domain.hi[static_cast<int>(face / 2)];
  }
  std::size_t ghost_count() const { return mirrors ? ghosts.size() : 0; }

  // The mirror particles for the current positions and h: every image of a real particle that
  // lies within 2 max h of a reflecting face (the largest support h_i + h_j, so every image that
  // can be a neighbour), including the edge and corner images across two or three faces. Serial
  // and in index order, so the images and their numbering are the same on any thread count.
  // With a skin the images within 2 max h + skin are made, and kept (their positions and h
  // follow their sources, place_ghosts()) while the lists are reused.
  void make_ghosts(double hmax) {
    if (!mirrors) return;
    const ParticleStore& P = s.particles_;
    const std::size_t n = P.size();
    const double* X[3] = {P.col(Field::x).data(), P.col(Field::y).data(), P.col(Field::z).data()};
    const double reach = 2.0 * hmax + skin_abs;
    ghosts.clear();
    for (std::size_t p = 0; p < n; ++p) {
      std::int8_t opt[3][3];
      int count[3];
      for (int a = 0; a < 3; ++a) {
        count[a] = 0;
        opt[a][count[a]++] = 0;
        const auto lo = static_cast<std::size_t>(2 * a), hi = lo + 1;
        if (mirror_face[lo] && X[a][p] - plane(lo) < reach) opt[a][count[a]++] = -1;
        if (mirror_face[hi] && plane(hi) - X[a][p] < reach) opt[a][count[a]++] = 1;
      }
      if (count[0] + count[1] + count[2] == 3) continue;
      for (int i = 0; i < count[0]; ++i) {
        for (int j = 0; j < count[1]; ++j) {
          for (int k = 0; k < count[2]; ++k) {
            if (i == 0 && j == 0 && k == 0) continue;
            ghosts.push_back({static_cast<std::uint32_t>(p), {opt[0][i], opt[1][j], opt[2][k]}});
          }
        }
      }
    }
    const std::size_t m = n + ghosts.size();
    for (auto* v : {&h, &h_mid, &ax, &ay, &az, &ex, &ey, &ez, &evx, &evy, &evz, &em, &erho, &ec}) {
      v->resize(m);
    }
    if (switch_on) alpha.resize(m);
    for (auto& v : a_stress) v.resize(m);
    place_ghosts();
  }

  // Positions (the reflections of their sources' current positions) and h of the images.
  void place_ghosts() {
    const ParticleStore& P = s.particles_;
    const std::size_t n = P.size();
    const double* X[3] = {P.col(Field::x).data(), P.col(Field::y).data(), P.col(Field::z).data()};
    double* E[3] = {ex.data(), ey.data(), ez.data()};
    for (int a = 0; a < 3; ++a) std::copy(X[a], X[a] + n, E[a]);
    for (std::size_t k = 0; k < ghosts.size(); ++k) {
      const Mirror& g = ghosts[k];
      for (int a = 0; a < 3; ++a) {
        const double x = X[a][g.src];
        const auto face = static_cast<std::size_t>(2 * a + (g.side[a] > 0 ? 1 : 0));
        E[a][n + k] = g.side[a] == 0 ? x : 2.0 * plane(face) - x;
      }
      h[n + k] = h[g.src];
    }
  }

  // Reflected copies of a per-particle vector (sign -1 on reflected axes) or scalar.
  void mirror_vector(double* vx, double* vy, double* vz, std::size_t n) const {
    for (std::size_t k = 0; k < ghosts.size(); ++k) {
      const Mirror& g = ghosts[k];
      vx[n + k] = g.side[0] != 0 ? -vx[g.src] : vx[g.src];
      vy[n + k] = g.side[1] != 0 ? -vy[g.src] : vy[g.src];
      vz[n + k] = g.side[2] != 0 ? -vz[g.src] : vz[g.src];
    }
  }
  void mirror_scalar(double* v, std::size_t n) const {
    for (std::size_t k = 0; k < ghosts.size(); ++k) v[n + k] = v[ghosts[k].src];
  }

  // The state the gather passes read, real then mirrored (velocity, mass, density, sound speed).
  void refresh_ghost_state() {
    if (!mirrors) return;
    const ParticleStore& P = s.particles_;
    const std::size_t n = P.size();
    const std::pair<Field, double*> copies[] = {
        {Field::vx, evx.data()},  {Field::vy, evy.data()},   {Field::vz, evz.data()},
        {Field::mass, em.data()}, {Field::rho, erho.data()}, {Field::soundspeed, ec.data()}};
    for (const auto& [f, to] : copies) {
      const double* from = P.col(f).data();
      std::copy(from, from + n, to);
    }
    mirror_vector(evx.data(), evy.data(), evz.data(), n);
    mirror_scalar(em.data(), n);
    mirror_scalar(erho.data(), n);
    mirror_scalar(ec.data(), n);
  }

  // A real particle that crossed a reflecting face during the drift is reflected back (position
  // and normal velocity, which keeps its kinetic energy): it met its own image. Then particles
  // beyond an outflow face leave, their energy booked as outflow (as MPM's outflow), with the
  // velocity and internal energy at t^n+1/2 (a^{n+1} is not made for them).
  void boundaries_after_drift() {
    ParticleStore& P = s.particles_;
    const std::size_t n = P.size();
    double* X[3] = {P.col(Field::x).data(), P.col(Field::y).data(), P.col(Field::z).data()};
    double* V[3] = {P.col(Field::vx).data(), P.col(Field::vy).data(), P.col(Field::vz).data()};
    if (mirrors) {
      for (std::size_t face = 0; face < 6; ++face) {
        if (!mirror_face[face]) continue;
        const int a = static_cast<int>(face / 2);
        const double p0 = plane(face), sign = face % 2 == 0 ? 1.0 : -1.0;
        for (std::size_t p = 0; p < n; ++p) {
          if (sign * (X[a][p] - p0) < 0.0) {
            X[a][p] = 2.0 * p0 - X[a][p];
            V[a][p] = -V[a][p];
          }
        }
      }
    }
    if (!outflows) return;
    leaving.assign(n, 0);
    const double* m = P.col(Field::mass).data();
    const double* e = P.col(Field::energy).data();
    const Vec3 g = s.config_.gravity;
    double carried = 0.0;
    for (std::size_t p = 0; p < n; ++p) {
      bool out = false;
      for (std::size_t face = 0; face < 6; ++face) {
        if (!outflow_face[face]) continue;
        const double d = X[face / 2][p] - plane(face);
        out = out || (face % 2 == 0 ? d < 0.0 : d > 0.0);
      }
      if (!out) continue;
      leaving[p] = 1;
      carried += 0.5 * m[p] * (V[0][p] * V[0][p] + V[1][p] * V[1][p] + V[2][p] * V[2][p]) +
                 m[p] * e[p] - m[p] * (g.x() * X[0][p] + g.y() * X[1][p] + g.z() * X[2][p]);
    }
    if (P.remove_if(leaving) == 0) return;
    if (switch_on) {
      // The switch's alpha leaves with its particle (the store keeps the order of the rest).
      std::size_t k = 0;
      for (std::size_t p = 0; p < n; ++p) {
        if (leaving[p] == 0) alpha[k++] = alpha[p];
      }
      alpha.resize(k);
    }
    lists_valid = false;
    if (P.size() == 0) {
      throw NumericalError("every particle has left through the outflow boundaries", 0,
                           s.clock_.step);
    }
    s.energy_.outflow += carried;
  }

  template <class F>
  void timed(Stage stage, F&& f) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    timings[stage].seconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }

  ks::PairInputs inputs() {
    ParticleStore& P = s.particles_;
    ks::PairInputs in;
    if (mirrors) {
      in.x = ex.data();
      in.y = ey.data();
      in.z = ez.data();
      in.vx = evx.data();
      in.vy = evy.data();
      in.vz = evz.data();
      in.mass = em.data();
      in.rho = erho.data();
      in.h = h.data();
      return in;
    }
    in.x = P.col(Field::x).data();
    in.y = P.col(Field::y).data();
    in.z = P.col(Field::z).data();
    in.vx = P.col(Field::vx).data();
    in.vy = P.col(Field::vy).data();
    in.vz = P.col(Field::vz).data();
    in.mass = P.col(Field::mass).data();
    in.rho = P.col(Field::rho).data();
    in.h = h.data();
    return in;
  }

  // Real particles; make_ghosts() extends the per-point arrays for the images (within the
  // capacity once the image count stops growing: no allocation).
  void resize(std::size_t n) {
    for (auto* v : {&h, &h_mid, &ax, &ay, &az, &heat, &mu, &kick_heat}) v->resize(n);
    for (auto& v : a_stress) v.resize(n);
  }

  // h = h_factor (m / rho)^{1/3} (see the header: dh/dt = h div v / 3 integrated exactly).
  void smoothing_lengths() {
    const ParticleStore& P = s.particles_;
    const double* m = P.col(Field::mass).data();
    const double* rho = P.col(Field::rho).data();
    const double f = s.sph_.h_factor;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, P.size(), kGrain),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t p = r.begin(); p < r.end(); ++p) {
                          h[p] = f * std::cbrt(m[p] / rho[p]);
                        }
                      });
  }

  // Builds the lists with the skin (sph.skin x 2 max h) and records the positions and h they
  // were built at.
  // With lists = false, only the cells of a build without a skin (NeighbourSearch::bin), for a
  // re-order: the same cells a full build gives, at a fraction of its cost.
  void build_search(bool with_skin = true, bool lists = true) {
    const ParticleStore& P = s.particles_;
    const std::size_t n = P.size();
    const double hmax = exact_max(n, [&](std::size_t p) { return h[p]; });
    skin_abs = with_skin ? s.sph_.skin * 2.0 * hmax : 0.0;
    if (!lists) {
      lists_valid = false;
      if (mirrors) {
        make_ghosts(hmax);
        search.bin(ex.data(), ey.data(), ez.data(), h.data(), n + ghosts.size());
      } else {
        search.bin(P.col(Field::x).data(), P.col(Field::y).data(), P.col(Field::z).data(), h.data(),
                   n);
      }
      return;
    }
    if (mirrors) {
      make_ghosts(hmax);
      search.build(ex.data(), ey.data(), ez.data(), h.data(), n + ghosts.size(), n, skin_abs);
    } else {
      search.build(P.col(Field::x).data(), P.col(Field::y).data(), P.col(Field::z).data(), h.data(),
                   n, n, skin_abs);
    }
    const double* X[3] = {P.col(Field::x).data(), P.col(Field::y).data(), P.col(Field::z).data()};
    for (auto* v : {&xb, &yb, &zb, &hb}) v->resize(n);
    std::copy(X[0], X[0] + n, xb.begin());
    std::copy(X[1], X[1] + n, yb.begin());
    std::copy(X[2], X[2] + n, zb.begin());
    std::copy(h.begin(), h.begin() + static_cast<std::ptrdiff_t>(n), hb.begin());
    lists_valid = true;
    ++builds;
  }

  // Whether the lists (and images) of the last build still hold every pair within support:
  // a pair outside the lists was >= h_i + h_j + skin apart at the build; since then its distance
  // fell by at most |dx_i| + |dx_j| and its support grew by at most dh_i+ + dh_j+, so twice the
  // largest |dx_p| + dh_p+ below the skin keeps it outside (an image moves and grows as its
  // source; an image not made was >= 2 max h + skin from every real point). 1 % of the skin is
  // kept for round-off. Exact maximum: any thread count decides alike.
  bool lists_still_cover() const {
    const ParticleStore& P = s.particles_;
    const std::size_t n = P.size();
    if (!lists_valid || xb.size() != n || !(skin_abs > 0.0)) return false;
    const auto x = P.col(Field::x), y = P.col(Field::y), z = P.col(Field::z);
    const double worst = exact_max(n, [&](std::size_t p) {
      const double dx = x[p] - xb[p], dy = y[p] - yb[p], dz = z[p] - zb[p];
      return std::sqrt(dx * dx + dy * dy + dz * dz) + std::max(0.0, h[p] - hb[p]);
    });
    return 2.0 * worst <= 0.99 * skin_abs;
  }

  // Steps 5-6 of the header: a pure function of the columns (and of the step count, which picks
  // the steps that re-order memory), so restore() can rebuild it bit for bit.
  void search_and_forces(bool may_reorder) {
    ParticleStore& P = s.particles_;
    timed(kSearch, [&] {
      check_state();
      const unsigned every = s.config_.reorder_interval;
      const bool reorder = may_reorder && every > 0 && s.clock_.step % every == 0;
      if (!reorder && lists_valid && xb.size() == P.size()) {
        // Verlet lists: keep the last build's lists while they cover every pair. The passes
        // run over the lists compacted to the pairs within support (the skin's entries
        // dropped) and the lists are in index order, so the sums are those of fresh lists, bit
        // for bit (tested), and a resumed run that builds afresh continues identically.
        smoothing_lengths();
        if (lists_still_cover()) {
          if (mirrors) place_ghosts();
          return;
        }
      }
      resize(P.size());
      smoothing_lengths();
      // Before a re-order, the cells that order memory must not depend on the skin (they would
      // change the particle order and so the bits): those of a build without one, binned only
      // (the lists would be stale after the re-order).
      build_search(!reorder, !reorder);
      if (reorder) {
        // Re-order each material group by cell (stable, so deterministic): the gather passes
        // then stream through memory. The lists are rebuilt for the new order.
        const auto cells = search.cells();
        order.resize(P.size());
        std::iota(order.begin(), order.end(), 0U);
        for (const Group& g : P.groups()) {
          std::stable_sort(order.begin() + static_cast<std::ptrdiff_t>(g.range.begin),
                           order.begin() + static_cast<std::ptrdiff_t>(g.range.end),
                           [&](std::uint32_t a, std::uint32_t b) { return cells[a] < cells[b]; });
        }
        P.permute(order);
        if (switch_on) {
          // new particle k is old particle order[k], as in ParticleStore::permute
          rho_n.resize(P.size());
          for (std::size_t k = 0; k < P.size(); ++k) rho_n[k] = alpha[order[k]];
          std::copy(rho_n.begin(), rho_n.end(), alpha.begin());
        }
        smoothing_lengths();
        build_search();
      }
    });
    timed(kForces, [&] { forces(); });
  }

  void forces() {
    ParticleStore& P = s.particles_;
    const std::size_t n = P.size();
    const double* rho = P.col(Field::rho).data();
    const double* sig[6];
    for (int c = 0; c < 6; ++c) sig[c] = P.col(kStressOrder[c]).data();
    const bool normalized = s.sph_.continuity == Continuity::normalized;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kGrain),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (int c = 0; c < 6; ++c) {
                          for (std::size_t p = r.begin(); p < r.end(); ++p) {
                            a_stress[c][p] = normalized ? sig[c][p] : sig[c][p] / (rho[p] * rho[p]);
                          }
                        }
                      });
    if (mirrors) {
      // sigma^{ab} of the image: negated when exactly one of a, b is a reflected axis.
      static constexpr int kAxes[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {1, 2}, {0, 2}};
      for (std::size_t k = 0; k < ghosts.size(); ++k) {
        const Mirror& g = ghosts[k];
        for (int c = 0; c < 6; ++c) {
          const bool flip = (g.side[kAxes[c][0]] != 0) != (g.side[kAxes[c][1]] != 0);
          const double v = a_stress[c][g.src];
          a_stress[c][n + k] = flip ? -v : v;
        }
      }
      refresh_ghost_state();
    }
    const ks::PairInputs in = inputs();
    ks::ForceInputs f;
    for (int c = 0; c < 6; ++c) f.a_stress[c] = a_stress[c].data();
    f.soundspeed = mirrors ? ec.data() : P.col(Field::soundspeed).data();
    f.normalized = normalized;
    f.viscosity.alpha = s.sph_.alpha;
    f.viscosity.beta = s.sph_.beta;
    if (switch_on) {
      if (mirrors) mirror_scalar(alpha.data(), n);
      f.alpha = alpha.data();
    }
    for (int d = 0; d < 3; ++d) f.gravity[d] = s.config_.gravity[d];
    if (pair_w.size() < search.pairs()) pair_w.resize(search.pairs());
    if (active.size() < search.pairs()) active.resize(search.pairs());
    active_count.resize(n);
    const ks::ForceOutputs out{ax.data(),   ay.data(), az.data(),
                               heat.data(), mu.data(), pair_w.data()};
    // Each list is first compacted to its pairs within support (a Verlet list's skin entries
    // dropped), which the next step's rates pass reuses: it runs at these same positions and h.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kPairGrain),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t i = r.begin(); i < r.end(); ++i) {
                          const std::size_t off = search.offset(i);
                          const std::size_t m = ks::compact_within_support(
                              in, search.begin_of(i), search.count(i), i, active.data() + off);
                          active_count[i] = static_cast<std::uint32_t>(m);
                          ks::forces_particle<simd::Batch>(in, f, active.data() + off, m, i, out,
                                                           off);
                        }
                      });
    // The images' a^n, for the next kick's viscous heat (rates pass).
    if (mirrors) mirror_vector(ax.data(), ay.data(), az.data(), n);
  }

  void kick(double dt_kick) {
    ParticleStore& P = s.particles_;
    double* v[3] = {P.col(Field::vx).data(), P.col(Field::vy).data(), P.col(Field::vz).data()};
    const double* a[3] = {ax.data(), ay.data(), az.data()};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, P.size(), kGrain),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (int d = 0; d < 3; ++d) {
                          for (std::size_t p = r.begin(); p < r.end(); ++p) {
                            v[d][p] += a[d][p] * dt_kick;
                          }
                        }
                      });
  }

  // The kick's viscous heat (made in the rates pass) into the energy at t^n, before the material
  // update reads it.
  void heat_from_kick() {
    ParticleStore& P = s.particles_;
    double* e = P.col(Field::energy).data();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, P.size(), kGrain),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t p = r.begin(); p < r.end(); ++p) e[p] += kick_heat[p];
                      });
  }

  // h^{n+1/2} for the rates pass. The forces at t^n and t^{n+1} use h(rho^n) and h(rho^{n+1});
  // the stress work matches their mean to second order only if the strain rate between them uses
  // the mean smoothing length too (with h^n the total energy error was first order in dt: 9e-4
  // and 4.6e-4 at CFL 0.3 and 0.15 for the colliding spheres without viscosity; with fixed h,
  // 8.9e-5 and 2.5e-5). rho^{n+1} is not known before the pass, so it is predicted from the
  // last step's volume change (the deps columns, which a checkpoint holds):
  // rho^{n+1} ~ rho^n / (1 + tr deps^{n-1/2} dt / dt_prev), an O(dt^2) error in h^{n+1/2}.
  void midpoint_smoothing_lengths(double dt) {
    ParticleStore& P = s.particles_;
    const double ratio = s.clock_.dt_prev > 0.0 ? dt / s.clock_.dt_prev : 0.0;
    const double* d[3] = {P.col(Field::deps_xx).data(), P.col(Field::deps_yy).data(),
                          P.col(Field::deps_zz).data()};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, P.size(), kGrain),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t p = r.begin(); p < r.end(); ++p) {
                          const double grow = 1.0 + (d[0][p] + d[1][p] + d[2][p]) * ratio;
                          // h ~ rho^{-1/3}; a predicted collapse (grow <= 0) keeps h^n.
                          h_mid[p] = grow > 0.0 ? 0.5 * h[p] * (1.0 + std::cbrt(grow)) : h[p];
                        }
                      });
  }

  void rates(double dt, double dt_kick) {
    ParticleStore& P = s.particles_;
    midpoint_smoothing_lengths(dt);
    if (mirrors) {
      mirror_scalar(h_mid.data(), P.size());
      refresh_ghost_state();  // v^{n+1/2} of the images
    }
    ks::PairInputs in = inputs();
    in.h = h_mid.data();
    ks::RateOutputs out;
    for (int c = 0; c < 6; ++c) out.deps[c] = P.col(kDepsOrder[c]).data();
    for (int c = 0; c < 3; ++c) out.dspin[c] = P.col(kSpinOrder[c]).data();
    out.rho = P.col(Field::rho).data();
    if (s.sph_.continuity == Continuity::normalized) {
      // rho^n of the neighbours, read while the pass overwrites the column (the images' copy,
      // erho, is already separate).
      if (!mirrors) {
        const auto r = P.col(Field::rho);
        rho_n.resize(P.size());
        std::copy(r.begin(), r.end(), rho_n.begin());
      }
      out.rho_n = mirrors ? erho.data() : rho_n.data();
    }
    ks::KickHeating kick;
    kick.pair_w = pair_w.data();
    kick.ax = ax.data();
    kick.ay = ay.data();
    kick.az = az.data();
    kick.dt_kick = dt_kick;
    kick.heat = kick_heat.data();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, P.size(), kPairGrain),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t i = r.begin(); i < r.end(); ++i) {
                          // The pairs within support at x^n and h^n, compacted by the forces
                          // pass of the last step (or of the constructor or restore()).
                          const std::size_t off = search.offset(i);
                          ks::rates_particle<simd::Batch>(in, active.data() + off, active_count[i],
                                                          i, dt, out, kick, off);
                        }
                      });
  }

  void material(double dt) {
    // SPH has its own pairwise viscosity (and heating): the constitutive kernel's bulk viscosity
    // is switched off so that shocks are not damped (and heated) twice.
    const ConstitutiveContext ctx{dt, 0.0, ArtificialViscosity{0.0, 0.0}};
    for (const Group& g : s.particles_.groups()) {
      if (g.range.empty()) continue;
      s.materials_[static_cast<std::size_t>(g.material)]->update(s.particles_, g.range, ctx);
    }
  }

  // The switch over this step (terms.hpp morris_monaghan_alpha): div v from the step's volume
  // change, tr deps / dt (= div v rho^n / rho^{n+1}, the rates pass's estimate), c^{n+1} from
  // the material update and h^{n+1/2}; the forces at t^{n+1} then use alpha^{n+1}.
  void evolve_switch(double dt) {
    if (!switch_on) return;
    ParticleStore& P = s.particles_;
    const double* d[3] = {P.col(Field::deps_xx).data(), P.col(Field::deps_yy).data(),
                          P.col(Field::deps_zz).data()};
    const double* c = P.col(Field::soundspeed).data();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, P.size(), kGrain),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t p = r.begin(); p < r.end(); ++p) {
                          const double div_v = (d[0][p] + d[1][p] + d[2][p]) / dt;
                          alpha[p] = ks::morris_monaghan_alpha(switch_k, alpha[p], div_v, c[p],
                                                               h_mid[p], dt);
                        }
                      });
  }

  void drift(double dt) {
    ParticleStore& P = s.particles_;
    double* X[3] = {P.col(Field::x).data(), P.col(Field::y).data(), P.col(Field::z).data()};
    const double* V[3] = {P.col(Field::vx).data(), P.col(Field::vy).data(),
                          P.col(Field::vz).data()};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, P.size(), kGrain),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (int d = 0; d < 3; ++d) {
                          for (std::size_t p = r.begin(); p < r.end(); ++p) X[d][p] += V[d][p] * dt;
                        }
                      });
  }

  // Energy at t^{n+1}: the velocity synchronised with the positions and stresses,
  // v^{n+1} = v^{n+1/2} + a^{n+1} dt^{n+1/2} / 2 (the first half of the next kick), and the
  // internal energy with the viscous heat of that same half kick.
  void energy() {
    const ParticleStore& P = s.particles_;
    const auto m = P.col(Field::mass), e = P.col(Field::energy);
    const auto vx = P.col(Field::vx), vy = P.col(Field::vy), vz = P.col(Field::vz);
    const auto x = P.col(Field::x), y = P.col(Field::y), z = P.col(Field::z);
    const double half = 0.5 * s.clock_.dt_prev;
    const Vec3 g = s.config_.gravity;
    EnergyBudget& E = s.energy_;
    E.kinetic = deterministic_sum(P.size(), [&](std::size_t p) {
      const double u = vx[p] + half * ax[p], v = vy[p] + half * ay[p], w = vz[p] + half * az[p];
      return 0.5 * m[p] * (u * u + v * v + w * w);
    });
    E.internal =
        deterministic_sum(P.size(), [&](std::size_t p) { return m[p] * (e[p] + half * heat[p]); });
    E.potential = deterministic_sum(P.size(), [&](std::size_t p) {
      return -m[p] * (g.x() * x[p] + g.y() * y[p] + g.z() * z[p]);
    });
    E.scale = std::max(E.scale, std::abs(E.kinetic) + std::abs(E.internal));
  }

  // Time step (Monaghan 1992, Sec. 4; Monaghan 1989, J. Comput. Phys. 82, 1): the Courant
  // condition with the viscous signal speed, dt_c = cfl h / (c + 1.2 (alpha c + beta max mu)),
  // and the force condition dt_f = cfl sqrt(h / |a|). c is the longitudinal speed c_p the
  // material model stores (damage included). Both minima are exact, so any thread count gives
  // the same dt. Unlike MPM's Eq. 34 there is no |v|: SPH has no grid to outrun.
  double stable_dt() const {
    const ParticleStore& P = s.particles_;
    const auto c = P.col(Field::soundspeed);
    // With the switch, the largest alpha it can reach (and beta = 2 alpha): the step does not
    // depend on the switch's state and is that of the constant default at alpha_max = 1.
    const double a_visc = switch_on ? s.sph_.alpha_max : s.sph_.alpha;
    const double b_visc = switch_on ? 2.0 * s.sph_.alpha_max : s.sph_.beta;
    const double cfl = s.config_.cfl;
    const double inf = std::numeric_limits<double>::infinity();
    const double dt = exact_min(P.size(), inf, [&](std::size_t p) {
      const double sig = c[p] + 1.2 * (a_visc * c[p] + b_visc * mu[p]);
      const double dt_c = sig > 0.0 ? cfl * h[p] / sig : inf;
      const double a = std::sqrt(ax[p] * ax[p] + ay[p] * ay[p] + az[p] * az[p]);
      const double dt_f = a > 0.0 ? cfl * std::sqrt(h[p] / a) : inf;
      return std::min(dt_c, dt_f);
    });
    return std::min(dt, s.config_.dt_max);
  }

  void next_dt() {
    Clock& clk = s.clock_;
    clk.dt = stable_dt();
    check_new_time_step(clk, s.config_.dt_min, "no sound speed, no force, and no dt_max set");
  }

  // The first particle (lowest index) whose state is not finite, or whose density is not
  // positive, stops the run with its name, field and step.
  void check_state() const {
    const ParticleStore& P = s.particles_;
    const std::size_t n = P.size();
    static constexpr Field kChecked[] = {Field::x,   Field::y,      Field::z,         Field::vx,
                                         Field::vy,  Field::vz,     Field::sxx,       Field::syy,
                                         Field::szz, Field::sxy,    Field::syz,       Field::sxz,
                                         Field::rho, Field::energy, Field::soundspeed};
    auto bad_value = [](Field f, double v) {
      return !std::isfinite(v) || (f == Field::rho && !(v > 0.0));
    };
    const std::size_t bad = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, n, kGrain), n,
        [&](const tbb::blocked_range<std::size_t>& r, std::size_t found) {
          for (const Field f : kChecked) {
            const auto c = P.col(f);
            for (std::size_t p = r.begin(); p < std::min(r.end(), found); ++p) {
              if (bad_value(f, c[p])) {
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
      if (bad_value(f, v)) {
        throw NumericalError(
            fmt::format("{} {} = {} at particle {} (id {}) at step {}, t = {:.6e} s",
                        f == Field::rho && std::isfinite(v) ? "non-positive" : "non-finite",
                        name_of(f), v, bad, P.col(IField::id)[bad], s.clock_.step, s.clock_.time),
            bad, s.clock_.step);
      }
    }
  }
};

SphSolver::SphSolver(SolverConfig config, SphConfig sph, ParticleStore particles,
                     std::vector<MaterialPtr> materials, int threads)
    : config_(std::move(config)),
      sph_(sph),
      particles_(std::move(particles)),
      materials_(std::move(materials)),
      threads_(threads) {
  if (!(config_.cfl > 0.0 && config_.cfl <= 1.0)) {
    throw std::invalid_argument(fmt::format("solver: cfl must be in (0, 1], got {}", config_.cfl));
  }
  if (!(sph_.h_factor > 0.0) || !std::isfinite(sph_.h_factor)) {
    throw std::invalid_argument(
        fmt::format("solver.sph: h_factor must be > 0, got {}", sph_.h_factor));
  }
  if (!(sph_.skin >= 0.0) || !std::isfinite(sph_.skin)) {
    throw std::invalid_argument(fmt::format("solver.sph: skin must be >= 0, got {}", sph_.skin));
  }
  if (sph_.viscosity_switch == ViscositySwitch::morris_monaghan &&
      !(sph_.alpha_min >= 0.0 && sph_.alpha_min <= sph_.alpha_max &&
        std::isfinite(sph_.alpha_max) && sph_.switch_decay > 0.0 &&
        std::isfinite(sph_.switch_decay))) {
    throw std::invalid_argument(fmt::format(
        "solver.sph: the viscosity switch needs 0 <= alpha_min <= alpha_max and switch_decay > 0, "
        "got alpha_min = {}, alpha_max = {}, switch_decay = {}",
        sph_.alpha_min, sph_.alpha_max, sph_.switch_decay));
  }
  if (!(sph_.alpha >= 0.0) || !(sph_.beta >= 0.0)) {
    throw std::invalid_argument(fmt::format(
        "solver.sph: alpha and beta must be >= 0, got {} and {}", sph_.alpha, sph_.beta));
  }
  static constexpr const char* kFaces[6] = {"x_lo", "x_hi", "y_lo", "y_hi", "z_lo", "z_hi"};
  for (std::size_t f = 0; f < 6; ++f) {
    const BoundaryKind k = config_.domain.faces[f];
    if (k == BoundaryKind::fixed) {
      throw std::invalid_argument(fmt::format(
          "solver.method = \"sph\": domain face {} is 'fixed' (no-slip walls are not implemented "
          "for SPH; 'slip', 'symmetry', 'outflow' and 'none' are)",
          kFaces[f]));
    }
    const int a = static_cast<int>(f / 2);
    const double bound = f % 2 == 0 ? config_.domain.lo[a] : config_.domain.hi[a];
    if (k != BoundaryKind::none && !std::isfinite(bound)) {
      throw std::invalid_argument(
          fmt::format("solver.method = \"sph\": domain face {} is '{}' but lies at {}", kFaces[f],
                      name_of(k), bound));
    }
  }
  if (config_.body_force) {
    throw std::invalid_argument("solver.method = \"sph\" does not take a body force yet");
  }
  check_solver_inputs(
      particles_, materials_,
      {Field::x, Field::y, Field::z, Field::vx, Field::vy, Field::vz, Field::mass, Field::rho});
  for (std::size_t f = 0; f < 6; ++f) {
    const BoundaryKind k = config_.domain.faces[f];
    if (k != BoundaryKind::symmetry && k != BoundaryKind::slip) continue;
    // A particle behind a reflecting face would overlap its own image.
    const int a = static_cast<int>(f / 2);
    const double bound = f % 2 == 0 ? config_.domain.lo[a] : config_.domain.hi[a];
    const auto x = particles_.col(a == 0 ? Field::x : a == 1 ? Field::y : Field::z);
    for (std::size_t p = 0; p < particles_.size(); ++p) {
      if (f % 2 == 0 ? x[p] < bound : x[p] > bound) {
        throw std::invalid_argument(fmt::format(
            "solver.method = \"sph\": particle {} ({} = {}) lies beyond the {} face {} at {}", p,
            "xyz"[a], x[p], name_of(k), kFaces[f], bound));
      }
    }
  }
  particles_.require(kSphFields);
  particles_.require(IField::id);
  for (const auto& m : materials_) particles_.require(m->fields());
  for (const Group& g : particles_.groups()) {
    materials_[static_cast<std::size_t>(g.material)]->initialise(particles_, g.range);
  }

  impl_ = std::make_unique<Impl>(*this, threads);
  impl_->arena.execute([&] {
    impl_->search_and_forces(true);
    impl_->energy();
    energy_.initial = energy_.total();
    energy_.scale = std::abs(energy_.kinetic) + std::abs(energy_.internal);
    impl_->next_dt();
  });
}

SphSolver::~SphSolver() = default;

const std::vector<StageTiming>& SphSolver::stage_timings() const {
  return impl_->timings;
}
const NeighbourSearch& SphSolver::neighbours() const {
  return impl_->search;
}
std::uint64_t SphSolver::neighbour_builds() const {
  return impl_->builds;
}
std::span<const double> SphSolver::smoothing_length() const {
  return {impl_->h.data(), particles_.size()};
}
std::span<const double> SphSolver::viscosity_alpha() const {
  if (!impl_->switch_on) return {};
  return {impl_->alpha.data(), particles_.size()};
}

void SphSolver::restore(const Clock& clock, const EnergyBudget& energy) {
  if (sph_.viscosity_switch != ViscositySwitch::none) {
    // The switch's alpha is a per-particle state the checkpoint does not hold (the store has no
    // column for it); restarting it at alpha_min would silently change the run.
    throw std::invalid_argument(
        "shatter resume: solver.sph.viscosity_switch = \"morris_monaghan\" cannot be resumed "
        "(the per-particle alpha is not in the checkpoint); rerun from the start");
  }
  clock_ = clock;
  energy_ = energy;
  impl_->lists_valid = false;
  // Steps 5-6 again on the restored columns (no re-order: the checkpointed store is already in
  // the order the original run had after its own re-order at this step).
  impl_->arena.execute([&] { impl_->search_and_forces(false); });
}

void SphSolver::restore(const Clock& clock, const EnergyBudget& energy, double /*internal_next*/) {
  restore(clock, energy);
}

void SphSolver::step() {
  impl_->arena.execute([&] {
    Impl& I = *impl_;
    const double dt = clock_.dt;
    const double dt_kick = 0.5 * (clock_.dt_prev + dt);
    I.timed(kKick, [&] {
      I.kick(dt_kick);
      if (constraint_) {
        const auto kinetic = [&] {
          const ParticleStore& P = particles_;
          const auto m = P.col(Field::mass);
          const auto vx = P.col(Field::vx), vy = P.col(Field::vy), vz = P.col(Field::vz);
          return deterministic_sum(P.size(), [&](std::size_t p) {
            return 0.5 * m[p] * (vx[p] * vx[p] + vy[p] * vy[p] + vz[p] * vz[p]);
          });
        };
        const double before = kinetic();
        constraint_(clock_.time + 0.5 * dt, particles_);
        energy_.boundary_work += before - kinetic();
      }
    });
    I.timed(kRates, [&] {
      I.rates(dt, dt_kick);
      I.heat_from_kick();
    });
    I.timed(kMaterial, [&] {
      I.material(dt);
      I.evolve_switch(dt);
    });
    I.timed(kDrift, [&] {
      I.drift(dt);
      I.boundaries_after_drift();
    });
    clock_.time += dt;
    clock_.dt_prev = dt;
    ++clock_.step;
    I.search_and_forces(true);
    I.timed(kEnergy, [&] {
      I.energy();
      I.next_dt();
    });
  });
}

void SphSolver::advance_to(double t) {
  // As Simulation::advance_to: a remainder below this fraction of the stable step is merged
  // into the previous step rather than taken alone (no sliver steps at output times).
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

}  // namespace shatter::sph
