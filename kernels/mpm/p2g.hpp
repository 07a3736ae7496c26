#pragma once
// Particle-to-grid scatter (App. A.2 steps 1 and 3; Eqs. 29, 32, 33) for the particles of one
// owner block. Contributions are summed into a padded scratch copy of the 2x2x2 blocks the
// stencils reach and then added to the grid, so the inner loop has fixed strides and the grid is
// touched once per node. Callers run owner blocks colour by colour (see SparseGrid).

#include <algorithm>
#include <cstdint>
#include <span>

#include "mpm/factors.hpp"
#include "mpm/lanes.hpp"
#include "mpm/stencil.hpp"

namespace shatter::kernels {

struct P2GParticles {
  const double *x, *y, *z, *vx, *vy, *vz, *mass, *rho, *size0;
  const double *sxx, *syy, *szz, *sxy, *syz, *sxz;  // null for a momentum-only scatter
  const double *bx, *by, *bz;  // body force per unit mass (Eq. 30); null when there is none
  // APIC affine velocity C_p, row-major (vgrad_xx .. vgrad_zz); read only by the kAffine scatter
  const double* vgrad[9];
  double inv_h;
  StencilCache stencil;  // kLoad in the engine (stored by its sort stage)
};

// Scratch grid: (kBlock + 2)^3 nodes reach every stencil node of the owner block's particles.
struct P2GScratch {
  static constexpr int kEdge = SparseGrid::kBlock + 2;
  static constexpr int kSize = kEdge * kEdge * kEdge;
  double m[kSize], px[kSize], py[kSize], pz[kSize], fx[kSize], fy[kSize], fz[kSize];
  // The FLIP scatter's sums side by side per node (lanes.hpp): mass and momentum in lanes 0-3,
  // force in lanes 4-6, lane 7 zero. The APIC scatter and the mass gradient use the arrays above.
  double q_[kSize * 8 + 7];  // see q()
  double* q(int i) { return align64(q_) + 8 * i; }
};

// The particle's own factors of the scatter: m_p, m_p v_p, the stress scaled by -V_p / h (so the
// node loop multiplies by the per-cell gradients only) and m_p b_p.
struct P2GPoint {
  double m, mvx, mvy, mvz;
  double sxx = 0.0, syy = 0.0, szz = 0.0, sxy = 0.0, syz = 0.0, sxz = 0.0;
  double mbx = 0.0, mby = 0.0, mbz = 0.0;
  double hoop = 0.0;  // axisymmetric: -V_p sigma_thetatheta / r_p, over 1/h as the stress above
};

// kAxisymmetric (r, z) = (x, z), the hoop direction y: the internal force on node I gains the
// hoop term -V_p sigma_thetathetap N_I(x_p) / r_p in its radial component (Sulsky & Schreyer
// 1996, CMAME 139, the axisymmetric weak form; NairnMPM MatPointAS::GetFintPlusFext, whose
// zDeriv is N_I / r_p). V_p is the point's ring volume, m_p / rho_p with the ring's mass.
template <bool kForce, bool kAxisymmetric = false>
P2GPoint p2g_point(const P2GParticles& in, std::uint32_t p) {
  P2GPoint q;
  q.m = in.mass[p];
  q.mvx = q.m * in.vx[p], q.mvy = q.m * in.vy[p], q.mvz = q.m * in.vz[p];
  if constexpr (kForce) {
    const double vol = q.m / in.rho[p];
    const double k = -vol * in.inv_h;
    q.sxx = k * in.sxx[p], q.syy = k * in.syy[p], q.szz = k * in.szz[p];
    q.sxy = k * in.sxy[p], q.syz = k * in.syz[p], q.sxz = k * in.sxz[p];
    if (in.bx) q.mbx = q.m * in.bx[p], q.mby = q.m * in.by[p], q.mbz = q.m * in.bz[p];
    // k sigma N h / r_p = -V sigma N / r_p: the node loop multiplies by N (cell units, as above)
    if constexpr (kAxisymmetric) q.hoop = q.syy / (in.x[p] * in.inv_h);
  }
  return q;
}

// Zeroes the scratch sums the scatter writes: the lanes, or the separate arrays.
template <bool kForce, bool kLanes>
void p2g_clear(P2GScratch& s) {
  if constexpr (kLanes) {
    std::fill(s.q(0), s.q(0) + 8 * P2GScratch::kSize, 0.0);
  } else {
    std::fill(std::begin(s.m), std::end(s.m), 0.0);
    std::fill(std::begin(s.px), std::end(s.px), 0.0);
    std::fill(std::begin(s.py), std::end(s.py), 0.0);
    std::fill(std::begin(s.pz), std::end(s.pz), 0.0);
    if constexpr (kForce) {
      std::fill(std::begin(s.fx), std::end(s.fx), 0.0);
      std::fill(std::begin(s.fy), std::end(s.fy), 0.0);
      std::fill(std::begin(s.fz), std::end(s.fz), 0.0);
    }
  }
}

// One particle into the lanes of the scratch nodes (the FLIP scatter). Each lane does the
// operations of the scalar loop (lanes.hpp): fma(c, N, sum) for mass and momentum, and for the
// force fma(mb, N, fma(s_z, g_z, fma(s_x, g_x, s_y g_y))) added to the sum, the FMAs GCC's
// -ffp-contract=fast made of the scalar expressions, so results are bitwise those of the
// scalar scatter.
// kAxisymmetric: the y gradient is zero (the degenerate y stencil), so the s_y g_y term carries
// the hoop force instead: s_y = (hoop, 0, 0) and g_y = N (sigma_xy = sigma_yz = 0, no torsion).
// St: a Stencil, or a StoredStencil read in place (stencil.hpp).
// kTable: with kForce, the node factors N, g from a NodeFactors table (factors.hpp; the same
// products, so the same bits; 1.17-1.22x for P2G in bench_p2g). kTable false: the products in
// the node loop, as before session 21, kept for bench_p2g's comparison.
template <bool kForce, bool kAxisymmetric = false, bool kTable = true, class St>
void p2g_lanes(const St& st, const P2GPoint& pt, P2GScratch& s) {
  constexpr int W = St::W;
  constexpr int E = P2GScratch::kEdge;
  const Lanes<4> q = Lanes<4>::set(pt.m, pt.mvx, pt.mvy, pt.mvz);
  const Lanes<4> sx = Lanes<4>::set(pt.sxx, pt.sxy, pt.sxz, 0.0);
  const Lanes<4> sy = kAxisymmetric ? Lanes<4>::set(pt.hoop, 0.0, 0.0, 0.0)
                                    : Lanes<4>::set(pt.sxy, pt.syy, pt.syz, 0.0);
  const Lanes<4> sz = Lanes<4>::set(pt.sxz, pt.syz, pt.szz, 0.0);
  const Lanes<4> mb = Lanes<4>::set(pt.mbx, pt.mby, pt.mbz, 0.0);
  // The table only for the force scatter: the momentum-only scatter (the remap's), one product
  // per node, ran 0.85x with it (bench_remap).
  constexpr bool kFactors = kTable && kForce;
  NodeFactors<W> t;
  if constexpr (kFactors) t.template fill<true>(st);
  for (int a = 0; a < W; ++a) {
    for (int b = 0; b < W; ++b) {
      const double wab = st.w[0][a] * st.w[1][b];
      const double gx_ab = st.dw[0][a] * st.w[1][b];
      const double gy_ab = st.w[0][a] * st.dw[1][b];
      const int row = ((st.off[0] + a) * E + (st.off[1] + b)) * E + st.off[2];
      const double(&f)[4][4] = t.v[a * W + b];
      for (int c = 0; c < W; ++c) {
        double* node = s.q(row + c);
        const double N = kFactors ? f[0][c] : wab * st.w[2][c];
        const Lanes<4> n = Lanes<4>::splat(N);
        fma(q, n, Lanes<4>::load(node)).store(node);
        if constexpr (kForce) {
          const Lanes<4> gx = Lanes<4>::splat(kFactors ? f[1][c] : gx_ab * st.w[2][c]);
          const Lanes<4> gy =
              kAxisymmetric ? n : Lanes<4>::splat(kFactors ? f[2][c] : gy_ab * st.w[2][c]);
          const Lanes<4> gz = Lanes<4>::splat(kFactors ? f[3][c] : wab * st.dw[2][c]);
          const Lanes<4> f4 = fma(mb, n, fma(sz, gz, fma(sx, gx, sy * gy)));  // Eqs. 29, 30
          (Lanes<4>::load(node + 4) + f4).store(node + 4);
        }
      }
    }
  }
}

// One particle into the separate scratch arrays (the APIC scatter: momentum per node
// m v + m C (x_I - x_p), whose x and y parts are fixed for a, b).
template <class Shape, bool kForce>
void p2g_affine(const P2GParticles& in, std::uint32_t p, const Stencil<Shape>& st,
                const double (&xi)[3], const P2GPoint& pt, P2GScratch& s) {
  constexpr int W = Shape::kWidth;
  constexpr int E = P2GScratch::kEdge;
  double mc[3][3], ox[W], oy[W], oz[W];
  for (int r = 0; r < 3; ++r) {
    for (int q = 0; q < 3; ++q) mc[r][q] = pt.m * in.vgrad[3 * r + q][p];
  }
  const double h = 1.0 / in.inv_h;
  for (int a = 0; a < W; ++a) {
    ox[a] = st.offset(0, a, xi[0], h);
    oy[a] = st.offset(1, a, xi[1], h);
    oz[a] = st.offset(2, a, xi[2], h);
  }
  for (int a = 0; a < W; ++a) {
    for (int b = 0; b < W; ++b) {
      const double wab = st.w[0][a] * st.w[1][b];
      const double gx_ab = st.dw[0][a] * st.w[1][b];
      const double gy_ab = st.w[0][a] * st.dw[1][b];
      const int row = ((st.off[0] + a) * E + (st.off[1] + b)) * E + st.off[2];
      const double qx = pt.mvx + (mc[0][0] * ox[a] + mc[0][1] * oy[b]);
      const double qy = pt.mvy + (mc[1][0] * ox[a] + mc[1][1] * oy[b]);
      const double qz = pt.mvz + (mc[2][0] * ox[a] + mc[2][1] * oy[b]);
      for (int c = 0; c < W; ++c) {
        const int i = row + c;
        const double N = wab * st.w[2][c];
        s.m[i] += pt.m * N;
        s.px[i] += (qx + mc[0][2] * oz[c]) * N;
        s.py[i] += (qy + mc[1][2] * oz[c]) * N;
        s.pz[i] += (qz + mc[2][2] * oz[c]) * N;
        if constexpr (kForce) {
          const double gx = gx_ab * st.w[2][c];
          const double gy = gy_ab * st.w[2][c];
          const double gz = wab * st.dw[2][c];
          s.fx[i] += pt.sxx * gx + pt.sxy * gy + pt.sxz * gz + pt.mbx * N;  // Eqs. 29, 30
          s.fy[i] += pt.sxy * gx + pt.syy * gy + pt.syz * gz + pt.mby * N;
          s.fz[i] += pt.sxz * gx + pt.syz * gy + pt.szz * gz + pt.mbz * N;
        }
      }
    }
  }
}

// Adds the scratch grid into the (up to 8) blocks it overlaps.
template <bool kForce, bool kLanes>
void p2g_flush(P2GScratch& s, const std::uint32_t* neighbours, SparseGrid::Nodes& nodes) {
  constexpr int E = P2GScratch::kEdge;
  constexpr int mask = SparseGrid::kBlock - 1;
  constexpr int bits = SparseGrid::kBlockBits;
  for (int lx = 0; lx < E; ++lx) {
    for (int ly = 0; ly < E; ++ly) {
      for (int lz = 0; lz < E; ++lz) {
        const int i = (lx * E + ly) * E + lz;
        double sm, spx, spy, spz, sfx = 0.0, sfy = 0.0, sfz = 0.0;
        if constexpr (kLanes) {
          const double* n = s.q(i);
          sm = n[0], spx = n[1], spy = n[2], spz = n[3];
          if constexpr (kForce) sfx = n[4], sfy = n[5], sfz = n[6];
        } else {
          sm = s.m[i], spx = s.px[i], spy = s.py[i], spz = s.pz[i];
          if constexpr (kForce) sfx = s.fx[i], sfy = s.fy[i], sfz = s.fz[i];
        }
        if (sm == 0.0) continue;
        const int sel = (lx >> bits) | ((ly >> bits) << 1) | ((lz >> bits) << 2);
        const std::size_t g =
            std::size_t{neighbours[sel]} * SparseGrid::kBlockNodes +
            static_cast<std::size_t>(SparseGrid::local(lx & mask, ly & mask, lz & mask));
        if constexpr (kForce) nodes.mass[g] += sm;  // the remap reuses step 1's mass
        nodes.px[g] += spx;
        nodes.py[g] += spy;
        nodes.pz[g] += spz;
        if constexpr (kForce) {
          nodes.fx[g] += sfx;
          nodes.fy[g] += sfy;
          nodes.fz[g] += sfz;
        }
      }
    }
  }
}

// kForce: also scatter the internal force -V_p sigma_p . grad N_I (Eq. 29); otherwise only mass
// and momentum (the MUSL remap of step 6 needs momentum alone).
// kAffine: APIC momentum m_p (v_p + C_p (x_I - x_p)) instead of m_p v_p (Jiang et al. 2015,
// Eq. 9 with C_p = B_p D_p^-1 taken as the grid velocity gradient). The shapes reproduce linear
// fields, sum_I N_I (x_I - x_p) = 0, so the affine term moves no net momentum.
// Without the affine term the node sums run in vector lanes (p2g_lanes).
// kAxisymmetric: the hoop force of the r-z mode (p2g_point); FLIP only (the scene refuses APIC).
template <class Shape, bool kForce, bool kAffine = false, bool kAxisymmetric = false,
          bool kTable = true>
void p2g_block(const P2GParticles& in, std::span<const std::uint32_t> particles,
               const SparseGrid::Coord& owner, const std::uint32_t* neighbours,
               SparseGrid::Nodes& nodes, P2GScratch& s) {
  constexpr bool kLanes = !kAffine;
  static_assert(!(kAffine && kAxisymmetric), "APIC carries no hoop term");
  p2g_clear<kForce, kLanes>(s);
  Stencil<Shape> st;
  const bool stored = in.stencil.mode == StencilCache::kLoad;
  if constexpr (kLanes && kRecomputedRows<Shape>) {
    if (in.stencil.mode == StencilCache::kRecompute) {  // the engine's uGIMP FLIP scatters
      for_each_recomputed<Shape, kForce>(in.stencil, particles,
                                         [&](const auto& stencil, std::uint32_t p) {
                                           p2g_lanes<kForce, kAxisymmetric, kTable>(
                                               stencil, p2g_point<kForce, kAxisymmetric>(in, p), s);
                                         });
      p2g_flush<kForce, kLanes>(s, neighbours, nodes);
      return;
    }
  }
  for (const std::uint32_t p : particles) {
    const P2GPoint pt = p2g_point<kForce, kAxisymmetric>(in, p);
    if (kLanes && stored) {  // the engine's FLIP scatters: the stored row read in place
      p2g_lanes<kForce, kAxisymmetric, kTable>(StoredStencil<Shape>(in.stencil, p), pt, s);
      continue;
    }
    const double x[3] = {in.x[p], in.y[p], in.z[p]};
    st.prepare(in.stencil, p, x, in.inv_h, 0.5 * in.size0[p] * in.inv_h, owner);
    if constexpr (kLanes) {
      p2g_lanes<kForce, kAxisymmetric, kTable>(st, pt, s);
    } else {
      const double xi[3] = {x[0] * in.inv_h, x[1] * in.inv_h, x[2] * in.inv_h};
      p2g_affine<Shape, kForce>(in, p, st, xi, pt, s);
    }
  }
  p2g_flush<kForce, kLanes>(s, neighbours, nodes);
}

// Mass gradient of one body's field, grad m_I = sum_p m_p grad N_I(x_p), whose direction gives
// the contact normal (Bardenhagen et al. 2000, Sec. 3; multi-velocity-field contact). Scatters
// only into body copies (blocks >= first_copy: nodes where several bodies meet), for particles
// of one owner block that share one neighbour list; same colouring as p2g_block. The stencils
// are the step's rows (in.stencil: stored, or recomputed for uGIMP), those of p2g_block. Before,
// they were computed here afresh from x / h rounded, then 1/2 and the first node subtracted (GCC
// fused neither, at -O1 nor in Release: the same bits as that form), where the rows fuse
// x / h - 1/2 and the remainder: a first node could differ from the key's across a block face
// (its zero-weight node then written outside the scratch window) and the weights by round-off.
template <class Shape>
void mass_gradient_block(const P2GParticles& in, std::span<const std::uint32_t> particles,
                         const SparseGrid::Coord& owner, const std::uint32_t* neighbours,
                         std::uint32_t first_copy, SparseGrid::Nodes& nodes, P2GScratch& s) {
  constexpr int W = Shape::kWidth;
  constexpr int E = P2GScratch::kEdge;
  std::fill(std::begin(s.m), std::end(s.m), 0.0);
  std::fill(std::begin(s.fx), std::end(s.fx), 0.0);
  std::fill(std::begin(s.fy), std::end(s.fy), 0.0);
  std::fill(std::begin(s.fz), std::end(s.fz), 0.0);
  Stencil<Shape> st;
  for (const std::uint32_t p : particles) {
    const double x[3] = {in.x[p], in.y[p], in.z[p]};
    st.prepare(in.stencil, p, x, in.inv_h, 0.5 * in.size0[p] * in.inv_h, owner);
    const double k = in.mass[p] * in.inv_h;
    for (int a = 0; a < W; ++a) {
      for (int b = 0; b < W; ++b) {
        const int row = ((st.off[0] + a) * E + (st.off[1] + b)) * E + st.off[2];
        for (int c = 0; c < W; ++c) {
          const int i = row + c;
          s.m[i] += st.w[0][a] * st.w[1][b] * st.w[2][c];
          s.fx[i] += k * st.dw[0][a] * st.w[1][b] * st.w[2][c];
          s.fy[i] += k * st.w[0][a] * st.dw[1][b] * st.w[2][c];
          s.fz[i] += k * st.w[0][a] * st.w[1][b] * st.dw[2][c];
        }
      }
    }
  }
  constexpr int mask = SparseGrid::kBlock - 1;
  constexpr int bits = SparseGrid::kBlockBits;
  for (int lx = 0; lx < E; ++lx) {
    for (int ly = 0; ly < E; ++ly) {
      for (int lz = 0; lz < E; ++lz) {
        const int i = (lx * E + ly) * E + lz;
        if (s.m[i] == 0.0) continue;
        const int sel = (lx >> bits) | ((ly >> bits) << 1) | ((lz >> bits) << 2);
        const std::uint32_t blk = neighbours[sel];
        if (blk < first_copy) continue;  // a shared node: no contact there
        const std::size_t g =
            std::size_t{blk - first_copy} * SparseGrid::kBlockNodes +
            static_cast<std::size_t>(SparseGrid::local(lx & mask, ly & mask, lz & mask));
        nodes.gx[g] += s.fx[i];
        nodes.gy[g] += s.fy[i];
        nodes.gz[g] += s.fz[i];
      }
    }
  }
}

}  // namespace shatter::kernels
