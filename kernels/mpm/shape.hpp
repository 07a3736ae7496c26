#pragma once
// Shape functions of the background grid (ISSUE engine item 4), evaluated per axis: the 3D weight
// of node (a, b, c) is wx[a] * wy[b] * wz[c] (tensor product), its gradient
// (dwx[a] wy[b] wz[c], wx[a] dwy[b] wz[c], wx[a] wy[b] dwz[c]) / h.
//
// All functions take the particle coordinate in cell units (xi = x / h) and return the first node
// of the stencil. Nodes sit at integer xi.

#include <cmath>

namespace shatter::kernels {

// Linear hat functions: 2 nodes per axis. Cheapest; suffers cell-crossing noise (MPM paper Sec. 2).
struct LinearShape {
  static constexpr int kWidth = 2;
  static int weights(double xi, double /*half_size*/, double w[kWidth], double dw[kWidth]) {
    const double fl = std::floor(xi);
    const double f = xi - fl;
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
  static int weights(double xi, double /*half_size*/, double w[kWidth], double dw[kWidth]) {
    const double fl = std::floor(xi - 0.5);
    const double f = xi - fl;  // in [0.5, 1.5): distance to the first node
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

  // Weight and derivative of one node at signed distance d = xi_p - xi_node (cell units).
  // The four pieces are all evaluated and one is selected (no branch), so that a loop over
  // particles vectorises; each piece is the same expression as in a branchy form, bit for bit.
  static void node(double d, double lp, double& w, double& dw) {
    const double ad = std::abs(d);
    const double s = d < 0.0 ? -1.0 : 1.0;
    const double r = 1.0 + lp - ad;
    const double w_in = 1.0 - (d * d + lp * lp) / (2.0 * lp), dw_in = -d / lp;
    const double w_mid = 1.0 - ad, dw_mid = -s;
    const double w_out = r * r / (4.0 * lp), dw_out = -s * r / (2.0 * lp);
    w = ad <= lp ? w_in : ad <= 1.0 - lp ? w_mid : ad <= 1.0 + lp ? w_out : 0.0;
    dw = ad <= lp ? dw_in : ad <= 1.0 - lp ? dw_mid : ad <= 1.0 + lp ? dw_out : 0.0;
  }

  static int weights(double xi, double half_size, double w[kWidth], double dw[kWidth]) {
    const double fl = std::floor(xi - 0.5);
    const double f = xi - fl;
    for (int a = 0; a < kWidth; ++a) node(f - a, half_size, w[a], dw[a]);
    return static_cast<int>(fl);
  }
};

}  // namespace shatter::kernels
