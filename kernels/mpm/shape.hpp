#pragma once
// Shape functions of the background grid (ISSUE engine item 4), evaluated per axis: the 3D weight
// of node (a, b, c) is wx[a] * wy[b] * wz[c] (tensor product), its gradient
// (dwx[a] wy[b] wz[c], wx[a] dwy[b] wz[c], wx[a] wy[b] dwz[c]) / h.
//
// All functions take the particle coordinate x and the inverse cell size 1/h (cell units: x = xi,
// 1/h = 1) and return the first node of the stencil. Nodes sit at integer x / h.

#include <cmath>

namespace shatter::kernels {

// The first stencil node of a particle at x along one axis, as a whole number: floor(x / h -
// shift), shift = 1/2 for the 3-wide stencils and 0 for the linear one, with x / h - shift one
// fused multiply-add (rounded once). The one expression every path takes it from: the sort's
// owner key (src/mpm/stages/sort.cpp), the stored rows (store_stencils), the recomputed uGIMP
// rows (gimp_rows::axis; recomputed_rows does these two operations in vector lanes) and the
// scalar Stencil::compute, all in kernels/mpm/stencil.hpp. Written as an explicit std::fma, the
// node no longer depends on whether the compiler contracts the product into the subtraction
// (GCC does at -O2 with -ffp-contract=fast, not at -O1): where the key and a row took it in two
// ways, a point at a cell centre (x / h - 1/2 an integer up to round-off) could lie one block
// away from its rows. With shift = 0 the FMA is the product alone, x / h rounded.
inline double first_node(double x, double inv_h, double shift) {
  return std::floor(std::fma(x, inv_h, -shift));
}

// Linear hat functions: 2 nodes per axis. Cheapest; suffers cell-crossing noise (MPM paper Sec. 2).
struct LinearShape {
  static constexpr int kWidth = 2;
  static constexpr double kShift = 0.0;
  static int weights(double x, double inv_h, double /*half_size*/, double w[kWidth],
                     double dw[kWidth]) {
    const double fl = first_node(x, inv_h, kShift);
    // x / h rounded, then the exact difference: the remainder as Release builds took it before
    // (x / h also fed the floor, so GCC fused nothing), written so that nothing can be fused.
    const double f = std::fma(x, inv_h, -0.0) - fl;
    w[0] = 1.0 - f;
    w[1] = f;
    dw[0] = -1.0;
    dw[1] = 1.0;
    return static_cast<int>(fl);
  }
};

// Quadratic B-spline: 3 nodes per axis, C1 across cells.
struct BSpline2Shape {
  static constexpr int kWidth = 3;
  static constexpr double kShift = 0.5;
  static int weights(double x, double inv_h, double /*half_size*/, double w[kWidth],
                     double dw[kWidth]) {
    const double fl = first_node(x, inv_h, kShift);
    const double f = std::fma(x, inv_h, -fl);  // in [0.5, 1.5): distance to the first node
    const double a = 1.5 - f;
    const double b = f - 1.0;
    const double c = f - 0.5;
    w[0] = 0.5 * a * a;
    w[1] = 0.75 - b * b;
    w[2] = 0.5 * c * c;
    dw[0] = -a;
    dw[1] = -2.0 * b;
    dw[2] = c;
    return static_cast<int>(fl);
  }
};

// uGIMP (Bardenhagen & Kober 2004), the paper's choice: the hat function convolved with the
// particle's undeformed characteristic function of half-width lp (cell units). With lp <= 1/2 the
// support (1 + lp) never exceeds 3 nodes.
struct GimpShape {
  static constexpr int kWidth = 3;
  static constexpr double kShift = 0.5;

  // Weight and derivative of one node at signed distance d = xi_p - xi_node (cell units).
  // The four pieces are all evaluated and one is selected (no branch), so that a loop over
  // particles vectorises; each piece is the same expression as in a branchy form, bit for bit.
  static void node(double d, double lp, double& w, double& dw) {
    const double ad = std::abs(d);
    const double s = d < 0.0 ? -1.0 : 1.0;
    const double r = 1.0 + lp - ad;
    // d^2 + lp^2 fused as GCC's contraction took it and as gimp_rows::axis writes it.
    const double w_in = 1.0 - std::fma(d, d, lp * lp) / (2.0 * lp), dw_in = -d / lp;
    const double w_mid = 1.0 - ad, dw_mid = -s;
    const double w_out = r * r / (4.0 * lp), dw_out = -s * r / (2.0 * lp);
    w = ad <= lp ? w_in : ad <= 1.0 - lp ? w_mid : ad <= 1.0 + lp ? w_out : 0.0;
    dw = ad <= lp ? dw_in : ad <= 1.0 - lp ? dw_mid : ad <= 1.0 + lp ? dw_out : 0.0;
  }

  // The remainder fused as the first node (and as gimp_rows::axis, stencil.hpp).
  static int weights(double x, double inv_h, double half_size, double w[kWidth],
                     double dw[kWidth]) {
    const double fl = first_node(x, inv_h, kShift);
    const double f = std::fma(x, inv_h, -fl);
    for (int a = 0; a < kWidth; ++a) node(f - a, half_size, w[a], dw[a]);
    return static_cast<int>(fl);
  }
};

}  // namespace shatter::kernels
