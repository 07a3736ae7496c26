#pragma once
// Cloud-in-cell assignment and interpolation on the gravity mesh (Hockney & Eastwood 1988,
// Eq. 5-40: the weights (1 - f), f per axis, f the point's fraction of its cell). The same
// weights deposit the mass and interpolate the field back, which with a centred difference and
// a symmetric Green's function makes the pair forces antisymmetric (H&E Sec. 5-4).

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "shatter/gravity/mesh_gravity.hpp"

namespace shatter::gravity {

// The mesh laid over the points: node (i, j, k) at origin + h (i, j, k).
struct MeshFrame {
  double origin[3] = {0.0, 0.0, 0.0};
  double h = 1.0;
};

// The points' bounding box, centred in an n-node mesh with spacing h = extent / (n - 4): the
// points then lie between nodes 1.5 and n - 2.5, so their CIC nodes are 1..n-2 and the centred
// difference there reads nodes 0..n-1, all inside the active mesh (mesh_gravity.cpp).
inline MeshFrame fit_frame(const MassPoints& pts, int n) {
  double lo[3], hi[3];
  const double* c[3] = {pts.x, pts.y, pts.z};
  for (int d = 0; d < 3; ++d) {
    lo[d] = pts.n ? *std::min_element(c[d], c[d] + pts.n) : 0.0;
    hi[d] = pts.n ? *std::max_element(c[d], c[d] + pts.n) : 0.0;
  }
  const double extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  MeshFrame f;
  // One point, or none: any spacing serves (a lone mass feels no force).
  f.h = extent > 0.0 ? extent / double(n - 4) : 1.0;
  for (int d = 0; d < 3; ++d) f.origin[d] = 0.5 * (lo[d] + hi[d]) - 0.5 * double(n - 1) * f.h;
  return f;
}

// A point's lower CIC node and weights along each axis.
struct CicStencil {
  int i[3];
  double w[3][2];
};
inline CicStencil cic(const MeshFrame& f, double x, double y, double z) {
  CicStencil s;
  const double p[3] = {x, y, z};
  for (int d = 0; d < 3; ++d) {
    const double u = (p[d] - f.origin[d]) / f.h;
    const double fl = std::floor(u);
    s.i[d] = static_cast<int>(fl);
    s.w[d][1] = u - fl;
    s.w[d][0] = 1.0 - s.w[d][1];
  }
  return s;
}

// Mass onto the mesh, point by point in order (one serial loop: the sums at every node are
// formed in the same order on any thread count). node(i, j, k) returns the mesh entry.
template <class Node>
void deposit(const MassPoints& pts, const MeshFrame& f, Node&& node) {
  for (std::size_t p = 0; p < pts.n; ++p) {
    const CicStencil s = cic(f, pts.x[p], pts.y[p], pts.z[p]);
    for (int a = 0; a < 2; ++a) {
      for (int b = 0; b < 2; ++b) {
        for (int c = 0; c < 2; ++c) {
          node(s.i[0] + a, s.i[1] + b, s.i[2] + c) += pts.m[p] * s.w[0][a] * s.w[1][b] * s.w[2][c];
        }
      }
    }
  }
}

// sum_{a,b} w_a w_b g(a - b) over the point's 8 nodes: its own contribution to the mesh
// potential at itself (in units of m_p/h), which the point-mass potential does not have.
inline double self_term(const CicStencil& s, double self_green) {
  // 1/|d| for |d|^2 = 1, 2, 3 (the corners of one cell), without a square root per pair.
  static const double inverse_root[4] = {0.0, 1.0, 1.0 / std::sqrt(2.0), 1.0 / std::sqrt(3.0)};
  double sum = 0.0;
  for (int a = 0; a < 8; ++a) {
    for (int b = 0; b < 8; ++b) {
      const int d[3] = {(a >> 2) - (b >> 2), ((a >> 1) & 1) - ((b >> 1) & 1), (a & 1) - (b & 1)};
      const int r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
      const double g = r2 == 0 ? self_green : inverse_root[r2];
      sum += s.w[0][a >> 2] * s.w[1][(a >> 1) & 1] * s.w[2][a & 1] * s.w[0][b >> 2] *
             s.w[1][(b >> 1) & 1] * s.w[2][b & 1] * g;
    }
  }
  return sum;
}

// The field at point p by the same weights: conv(i, j, k) the convolution sum_j m_j g (units
// 1/h), acc(d, i, j, k) the mesh acceleration. Writes only p's own entries of `out`.
template <class Conv, class Acc>
void interpolate_point(const MassPoints& pts, const MeshFrame& f, std::size_t p, double G,
                       Conv&& conv, Acc&& acc, double self_green, const FieldOut& out) {
  const CicStencil s = cic(f, pts.x[p], pts.y[p], pts.z[p]);
  double phi = 0.0, a[3] = {0.0, 0.0, 0.0};
  for (int n = 0; n < 8; ++n) {
    const int i = s.i[0] + (n >> 2), j = s.i[1] + ((n >> 1) & 1), k = s.i[2] + (n & 1);
    const double w = s.w[0][n >> 2] * s.w[1][(n >> 1) & 1] * s.w[2][n & 1];
    if (out.phi) phi += w * conv(i, j, k);
    if (out.ax) {
      for (int d = 0; d < 3; ++d) a[d] += w * acc(d, i, j, k);
    }
  }
  if (out.phi) out.phi[p] = -G / f.h * (phi - pts.m[p] * self_term(s, self_green));
  if (out.ax) {
    out.ax[p] = a[0];
    out.ay[p] = a[1];
    out.az[p] = a[2];
  }
}

}  // namespace shatter::gravity
