// The cubic-spline kernel (kernels/sph/cubic_spline.hpp; Monaghan & Lattanzio 1985): analytic
// normalisation and gradient moments, derivative consistency, and its discrete sums on the
// cubic lattice the scenes fill bodies with.

#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "sph/cubic_spline.hpp"

namespace shatter::kernels::sph {
namespace {

// Composite Simpson over [a, b] with n (even) intervals. The integrands below are polynomials of
// degree <= 6 on each kernel branch (integrated branch by branch), so with n = 2000 the error
// bound (b - a) h^4 max|f''''| / 180 is below 1e-13 of the integral.
template <class F>
double simpson(F&& f, double a, double b, int n) {
  const double dx = (b - a) / n;
  double s = f(a) + f(b);
  for (int k = 1; k < n; ++k) s += f(a + k * dx) * (k % 2 == 1 ? 4.0 : 2.0);
  return s * dx / 3.0;
}

TEST(CubicSpline, IntegratesToOne) {
  // int W dV = 4 pi int_0^{2h} W r^2 dr = 1 (the kernel's normalisation sigma = 1 / (pi h^3)).
  for (const double h : {1e-3, 0.37, 2.0}) {
    auto f = [h](double r) { return 4.0 * kPi * r * r * cubic_w(r, h); };
    const double integral = simpson(f, 0.0, h, 2000) + simpson(f, h, 2.0 * h, 2000);
    EXPECT_NEAR(integral, 1.0, 1e-12) << "h = " << h;  // Simpson bound above, with margin
  }
}

TEST(CubicSpline, GradientReproducesTheIdentity) {
  // int (x - x')_a dW/dx_b dV' = delta_ab (integration by parts of int W = 1): for a radial
  // kernel this is -(4 pi / 3) int_0^{2h} r^3 dW/dr dr = 1. This is the continuum statement that
  // the SPH velocity gradient (Eq. 18) of a linear field is exact.
  for (const double h : {1e-3, 0.37, 2.0}) {
    auto f = [h](double r) { return -(4.0 * kPi / 3.0) * r * r * r * cubic_dw(r, h); };
    const double integral = simpson(f, 0.0, h, 2000) + simpson(f, h, 2.0 * h, 2000);
    EXPECT_NEAR(integral, 1.0, 1e-12) << "h = " << h;
  }
}

TEST(CubicSpline, DerivativeMatchesFiniteDifferenceAndVanishesAtSupport) {
  const double h = 0.5;
  double max_dw = 0.0, max_err = 0.0;
  for (int k = 1; k < 400; ++k) {
    const double r = 2.0 * h * k / 400.0;
    const double d = 1e-6 * h;
    const double fd = (cubic_w(r + d, h) - cubic_w(r - d, h)) / (2.0 * d);
    max_dw = std::max(max_dw, std::abs(cubic_dw(r, h)));
    max_err = std::max(max_err, std::abs(fd - cubic_dw(r, h)));
    // (1/r) dW/dr is what the pair terms use.
    EXPECT_NEAR(cubic_f(r, h) * r, cubic_dw(r, h), 1e-14 * std::abs(cubic_dw(r, h)) + 1e-300);
  }
  // Central differences with d = 1e-6 h: truncation O(d^2 W''') ~ 1e-12 relative, and the
  // second derivative jumps at q = 1 and 2 (M4 is C2 but W''' jumps): 1e-7 relative covers both.
  EXPECT_LT(max_err, 1e-7 * max_dw);
  EXPECT_EQ(cubic_w(2.0 * h, h), 0.0);
  EXPECT_EQ(cubic_dw(2.0 * h, h), 0.0);
  // Continuity of W and dW/dr at q = 1 (the two branches meet).
  EXPECT_NEAR(cubic_w(h * (1 - 1e-12), h), cubic_w(h, h), 1e-10 * cubic_w(0.0, h));
  EXPECT_NEAR(cubic_dw(h * (1 - 1e-12), h), cubic_dw(h, h), 1e-10 * max_dw);
}

// Discrete sums over a cubic lattice of spacing s around an interior point, with h = 1.2 s (the
// SPH default h_factor): the kernel deficiency the solver lives with in the bulk.
struct LatticeSums {
  double w = 0.0;       // sum_j V W_ij          (1 in the continuum)
  double m[3][3] = {};  // sum_j V (x_j - x_i)_a (grad_i W_ij)_b  (delta_ab)
  int neighbours = 0;   // points within 2h (excluding i)
};

LatticeSums lattice_sums(double s, double h) {
  LatticeSums out;
  const double V = s * s * s;
  for (int a = -4; a <= 4; ++a) {
    for (int b = -4; b <= 4; ++b) {
      for (int c = -4; c <= 4; ++c) {
        const double d[3] = {a * s, b * s, c * s};  // x_j - x_i
        const double r = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        out.w += V * cubic_w(r, h);
        if (r == 0.0 || r >= 2.0 * h) continue;
        ++out.neighbours;
        const double F = cubic_f(r, h);  // grad_i W_ij = F (x_i - x_j) = -F d
        for (int p = 0; p < 3; ++p) {
          for (int q = 0; q < 3; ++q) out.m[p][q] += V * d[p] * (-F * d[q]);
        }
      }
    }
  }
  return out;
}

TEST(CubicSpline, LatticeSumsAtTheDefaultSmoothingLength) {
  const LatticeSums L = lattice_sums(0.01, 0.012);
  // 56 lattice points lie within 2.4 spacings (6 + 12 + 8 + 6 + 24 = 56 with |n|^2 <= 5).
  EXPECT_EQ(L.neighbours, 56);
  // The kernel's deficiency on this lattice: sum V W = 1.00081 and M = 0.98169 I (lattice
  // symmetry makes M isotropic), i.e. the velocity gradient of Eq. 18 reads 1.8 % low in the bulk
  // at h = 1.2 s (0.65 % at h = 1.3 s, +0.6 % at 1.1 s). The reference values were computed
  // independently (a separate Python implementation of the same sums, double precision), so
  // the tolerance is round-off over ~700 terms.
  EXPECT_NEAR(L.w, 1.0008095483584358, 1e-12);
  for (int p = 0; p < 3; ++p) {
    for (int q = 0; q < 3; ++q) {
      EXPECT_NEAR(L.m[p][q], p == q ? 0.9816885670799698 : 0.0, 1e-12) << p << q;
    }
  }
}

TEST(CubicSpline, LanesMatchTheReferenceInEveryLane) {
  // cubic_f_lanes (the gather passes' branch-free form, scalar and SIMD) against cubic_f: both
  // branches, the edges q = 1 and 2, beyond the support, and r = 0 (where it returns 0 by
  // design). Its 1 / h and h / r come from one division, a few roundings more than cubic_f's
  // formula, so q differs by a few ulp, which t = 2 - q magnifies near the edge by q / t: the
  // bound is 1e-14 (~45 eps) of the kernel's scale |F(0)| = 3 / (pi h^5), the size the pair
  // terms are summed against (measured: 1.2e-15 of it); exact 0 outside the support. The
  // scalar instantiation is held to the same bound (not to the SIMD lanes' bits: a compiler may
  // contract the two into FMAs differently).
  using B = simd::Batch;
  constexpr std::size_t W = simd::kWidth;
  const double h = 0.37;
  std::vector<double> r;
  for (int k = 1; k <= 410; ++k) r.push_back(2.05 * h * k / 410.0);
  r.push_back(h);
  r.push_back(2.0 * h);
  while (r.size() % W != 0) r.push_back(0.5 * h);
  const double scale = std::abs(cubic_f(0.0, h));
  double worst = 0.0;
  for (std::size_t k = 0; k < r.size(); k += W) {
    alignas(64) double out[W];
    cubic_f_lanes(B::load_unaligned(&r[k]), B(h)).store_aligned(out);
    for (std::size_t l = 0; l < W; ++l) {
      const double ref = cubic_f(r[k + l], h);
      EXPECT_NEAR(out[l], ref, 1e-14 * scale) << "r / h = " << r[k + l] / h;
      worst = std::max(worst, std::abs(out[l] - ref) / scale);
      EXPECT_NEAR(cubic_f_lanes(r[k + l], h), ref, 1e-14 * scale)
          << "scalar, r / h = " << r[k + l] / h;
      if (r[k + l] >= 2.0 * h) {
        EXPECT_EQ(out[l], 0.0);
      }
    }
  }
  EXPECT_EQ(cubic_f_lanes(0.0, h), 0.0);
  std::printf("cubic_f_lanes against cubic_f: largest difference %.2e of |F(0)|\n", worst);
}

}  // namespace
}  // namespace shatter::kernels::sph
