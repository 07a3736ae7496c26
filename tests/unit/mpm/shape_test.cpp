#include <gtest/gtest.h>

#include <random>

#include "mpm/shape.hpp"

using namespace shatter::kernels;

namespace {

// Partition of unity, zero-sum gradients and linear reproduction hold to round-off for every
// shape function; 1e-13 leaves a few ulps for the sums of 2-3 terms of order 1.
constexpr double kRoundOff = 1e-13;

template <class Shape>
void check_consistency(double half_size) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-50.0, 50.0);
  for (int k = 0; k < 2000; ++k) {
    const double xi = u(rng);
    double w[Shape::kWidth], dw[Shape::kWidth];
    const int base = Shape::weights(xi, 1.0, half_size, w, dw);
    double sw = 0, sdw = 0, sx = 0, sxdw = 0;
    for (int a = 0; a < Shape::kWidth; ++a) {
      EXPECT_GE(w[a], -kRoundOff);
      sw += w[a];
      sdw += dw[a];
      sx += w[a] * (base + a);
      sxdw += dw[a] * (base + a);
    }
    EXPECT_NEAR(sw, 1.0, kRoundOff) << xi;
    EXPECT_NEAR(sdw, 0.0, kRoundOff) << xi;
    EXPECT_NEAR(sx, xi, 1e-11) << xi;         // reproduces x; absolute, |x| <= 50
    EXPECT_NEAR(sxdw, 1.0, kRoundOff) << xi;  // gradient of x is 1
  }
}

}  // namespace

TEST(ShapeFunctions, LinearIsConsistent) {
  check_consistency<LinearShape>(0.25);
}
TEST(ShapeFunctions, BSplineIsConsistent) {
  check_consistency<BSpline2Shape>(0.25);
}
TEST(ShapeFunctions, GimpIsConsistentForTwoPointsPerCell) {
  check_consistency<GimpShape>(0.25);
}
TEST(ShapeFunctions, GimpIsConsistentForOnePointPerCell) {
  check_consistency<GimpShape>(0.5);
}

TEST(ShapeFunctions, GimpIsContinuousAcrossCellFaces) {
  // The point of GIMP: no jump in the weights when a particle crosses a node (MPM paper Sec. 2).
  // A step of 1e-9 cell changes a C0 function by O(1e-9).
  for (const double x0 : {0.0, 0.25, 0.5, 0.75, 1.0, 1.25}) {
    double wa[3], da[3], wb[3], db[3];
    const int ba = GimpShape::weights(x0 - 1e-9, 1.0, 0.25, wa, da);
    const int bb = GimpShape::weights(x0 + 1e-9, 1.0, 0.25, wb, db);
    for (int node = -2; node <= 4; ++node) {
      const double fa = (node - ba >= 0 && node - ba < 3) ? wa[node - ba] : 0.0;
      const double fb = (node - bb >= 0 && node - bb < 3) ? wb[node - bb] : 0.0;
      EXPECT_NEAR(fa, fb, 1e-8) << "node " << node << " at " << x0;
    }
  }
}
