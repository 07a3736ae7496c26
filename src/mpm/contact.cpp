#include "mpm/contact.hpp"

#include <algorithm>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

namespace shatter::mpm {
namespace {

// Pairs where one body's nodal mass is below this fraction of the other's are not corrected.
constexpr double kMinMassRatio = 0.01;

// Kinetic energy of the body fields present at one node, 0.5 m |v|^2 summed over the copies.
template <class Node>
double node_kinetic_energy(const SparseGrid::Nodes& N, std::uint32_t count, Node node,
                           double empty_mass) {
  double e = 0.0;
  for (std::uint32_t k = 0; k < count; ++k) {
    const std::size_t i = node(k);
    if (N.mass[i] <= empty_mass) continue;
    e += 0.5 * N.mass[i] * (N.px[i] * N.px[i] + N.py[i] * N.py[i] + N.pz[i] * N.pz[i]);
  }
  return e;
}

// The contact normal from a into b, or false where neither body has a mass gradient.
// g = sum_p m_p grad N_I(x_p) points out of a body at its surface (N_I falls towards the
// particles beyond the node). The normal is that of the body with the larger mass gradient, the
// other taking its opposite ("maximum volume gradient", Nairn 2013; Bardenhagen et al. 2000 use
// each body's own gradient): one collinear normal for the pair, antisymmetric in (a, b), so the
// correction is equal and opposite. Measured against the difference g_a - g_b (the
// gradient-weighted average): that one tilts at the front edge of a sliding block and drags it
// at 0.05 g with no friction; this one takes the flat face's normal there
// (docs/verification.md, contact).
bool contact_normal(const SparseGrid::Nodes& N, std::size_t ga_i, std::size_t gb_i, double n[3]) {
  const double ga[3] = {N.gx[ga_i], N.gy[ga_i], N.gz[ga_i]};
  const double gb[3] = {N.gx[gb_i], N.gy[gb_i], N.gz[gb_i]};
  const bool a_leads = ga[0] * ga[0] + ga[1] * ga[1] + ga[2] * ga[2] >=
                       gb[0] * gb[0] + gb[1] * gb[1] + gb[2] * gb[2];
  for (int d = 0; d < 3; ++d) n[d] = a_leads ? ga[d] : -gb[d];
  const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  if (!(len > 0.0)) return false;
  for (int d = 0; d < 3; ++d) n[d] /= len;
  return true;
}

// One pair of body fields at a node (ia, ib; gradients at ga_i, gb_i), friction coefficient mu.
// Pass 0 corrects the velocities before the momentum update, v - a dt, in p* only; pass 1 the
// updated ones, also handed to f* as an acceleration when dt > 0. False when nothing changed.
bool correct_pair(SparseGrid::Nodes& N, std::size_t ia, std::size_t ib, std::size_t ga_i,
                  std::size_t gb_i, double mu, int pass, double dt) {
  const double ma = N.mass[ia], mb = N.mass[ib];
  double n[3];
  if (!contact_normal(N, ga_i, gb_i, n)) return false;
  // pass 0: the velocities before the momentum update, v - a dt
  const double back = pass == 0 ? dt : 0.0;
  const double vr[3] = {N.px[ia] - N.px[ib] - back * (N.fx[ia] - N.fx[ib]),
                        N.py[ia] - N.py[ib] - back * (N.fy[ia] - N.fy[ib]),
                        N.pz[ia] - N.pz[ib] - back * (N.fz[ia] - N.fz[ib])};
  const double vn = vr[0] * n[0] + vr[1] * n[1] + vr[2] * n[2];
  // Bardenhagen et al. (2000) Eq. 11: contact only while approaching; a separating pair
  // (vn <= 0) keeps its own velocities: no tension across the interface.
  if (!(vn > 0.0)) return false;
  // Reduced mass: the momentum a exchanges with b to share one normal velocity,
  // m_a (v_a - v_cm).n = m_a m_b / (m_a + m_b) (v_a - v_b).n (Eq. 12).
  const double mred = ma * mb / (ma + mb);
  const double pn = mred * vn;
  const double vt[3] = {vr[0] - vn * n[0], vr[1] - vn * n[1], vr[2] - vn * n[2]};
  const double vt_len = std::sqrt(vt[0] * vt[0] + vt[1] * vt[1] + vt[2] * vt[2]);
  // Coulomb (Eqs. 13-14): the tangential exchange stops the slip, or is capped at mu times the
  // normal one.
  const double pt = std::min(mu * pn, mred * vt_len);
  const double kt = vt_len > 0.0 ? pt / vt_len : 0.0;
  const double dp[3] = {-pn * n[0] - kt * vt[0], -pn * n[1] - kt * vt[1], -pn * n[2] - kt * vt[2]};
  const double ia_m = 1.0 / ma, ib_m = 1.0 / mb;
  const double inv_dt = dt > 0.0 ? 1.0 / dt : 0.0;
  double* v[3] = {N.px.data(), N.py.data(), N.pz.data()};
  double* f[3] = {N.fx.data(), N.fy.data(), N.fz.data()};
  for (int d = 0; d < 3; ++d) {
    v[d][ia] += dp[d] * ia_m;
    v[d][ib] -= dp[d] * ib_m;
    if (dt > 0.0 && pass == 1) {
      f[d][ia] += dp[d] * ia_m * inv_dt;
      f[d][ib] -= dp[d] * ib_m * inv_dt;
    }
  }
  return true;
}

}  // namespace

Contact::Contact(const ContactConfig& config) : friction_(config.friction) {
  // The last entry naming a pair wins (ContactConfig::coefficient).
  for (const ContactPair& p : config.pairs) pairs_[key(p.a, p.b)] = p.friction;
}

double Contact::resolve_node(SparseGrid& grid, const SparseGrid::Meeting& mt, int l,
                             const Boundaries& bc, double dt, double empty_mass) const {
  auto& N = grid.nodes();
  const std::size_t g0 = grid.shared_blocks() * SparseGrid::kBlockNodes;
  auto node = [&](std::uint32_t k) {
    return std::size_t{mt.first_copy + k} * SparseGrid::kBlockNodes + static_cast<std::size_t>(l);
  };
  int present = 0;
  for (std::uint32_t k = 0; k < mt.count; ++k) present += N.mass[node(k)] > empty_mass ? 1 : 0;
  if (present < 2) return 0.0;
  const double before = node_kinetic_energy(N, mt.count, node, empty_mass);
  bool touched = false;
  // Two passes (Nairn et al. 2020; NairnMPM's MASS_MOMENTUM_CALL and UPDATE_MOMENTUM_CALL):
  // pass 0 corrects the velocities the particles brought to the grid, v^n = v^{n+1} - a dt, and
  // changes only the nodal velocity (so v^{n+1} and the positions and strain rate made from it),
  // not the acceleration the particles take; pass 1 corrects the updated v^{n+1} and hands that
  // change to the particles as an acceleration. With pass 1 alone the approach velocity the
  // particles carry into contact was cancelled at the particles in one step, a perfectly
  // inelastic collision of the nodal masses (an elastic sphere kept 0.076 of its approach
  // momentum); with pass 0 the particles keep it until the stress the corrected velocity field
  // builds stops them, as in the single shared field.
  const int first_pass = dt > 0.0 ? 0 : 1;
  for (int pass = first_pass; pass < 2; ++pass) {
    // Pairs in a fixed order (a Gauss-Seidel sweep where three or more bodies meet).
    for (std::uint32_t a = 0; a < mt.count; ++a) {
      const std::size_t ia = node(a);
      const double ma = N.mass[ia];
      if (ma <= empty_mass) continue;
      for (std::uint32_t b = a + 1; b < mt.count; ++b) {
        const std::size_t ib = node(b);
        const double mb = N.mass[ib];
        if (mb <= empty_mass) continue;
        // A field this light against the other is a stencil fringe: its trial velocity is
        // F dt / m of a few particles' tails and rings; as contact acts only on approach, that
        // noise was rectified into a push that gave two head-on cubes 1.8x their energy (linear
        // shapes) until such pairs were left out.
        if (std::min(ma, mb) < kMinMassRatio * std::max(ma, mb)) continue;
        const double mu =
            friction(grid.copy_body(mt.first_copy + a), grid.copy_body(mt.first_copy + b));
        touched |= correct_pair(N, ia, ib, ia - g0, ib - g0, mu, pass, dt);
      }
    }
  }
  if (!touched) return 0.0;
  if (bc.constrained()) {
    const SparseGrid::Coord c = grid.coord(mt.block);
    const std::int64_t g[3] = {std::int64_t{c.x} * 4 + l / 16, std::int64_t{c.y} * 4 + (l / 4) % 4,
                               std::int64_t{c.z} * 4 + l % 4};
    for (std::uint32_t k = 0; k < mt.count; ++k) {
      const std::size_t i = node(k);
      if (N.mass[i] <= empty_mass) continue;
      // A correction along a normal with a component across a wall is taken out again.
      bc.constrain(g, N.px[i], N.py[i], N.pz[i]);
      if (dt > 0.0) bc.constrain(g, N.fx[i], N.fy[i], N.fz[i]);
    }
  }
  return before - node_kinetic_energy(N, mt.count, node, empty_mass);
}

double Contact::resolve(SparseGrid& grid, const Boundaries& bc, double dt,
                        double empty_mass) const {
  const auto meetings = grid.meetings();
  // Each meeting block owns its copies: blocks never share a node, so any split is race-free;
  // the fixed grain and the deterministic reduce make the energy sum thread-count independent.
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<std::size_t>(0, meetings.size(), 4), 0.0,
      [&](const tbb::blocked_range<std::size_t>& r, double removed) {
        for (std::size_t j = r.begin(); j < r.end(); ++j) {
          for (int l = 0; l < SparseGrid::kBlockNodes; ++l) {
            removed += resolve_node(grid, meetings[j], l, bc, dt, empty_mass);
          }
        }
        return removed;
      },
      std::plus<>());
}

}  // namespace shatter::mpm
