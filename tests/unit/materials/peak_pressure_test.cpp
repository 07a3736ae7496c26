// The peak-pressure tracer (issue 13 item 3): every composed material keeps, per point, the
// largest EOS pressure it has seen, in the update that both solvers call once per group and step.

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "material_test_support.hpp"
#include "shatter/core/particles.hpp"
#include "shatter/material/catalogue.hpp"

namespace shatter {
namespace {

using test::kEngineFields;

TEST(PeakPressure, HoldsTheLargestPressureThroughCompressionAndRelease) {
  // Isotropic compression of sod_gas in 10 steps, then release in 10: the tracer equals the
  // running maximum of the pressure column exactly (it is that maximum, no arithmetic).
  const auto m = make_material(MaterialCatalogue::builtin().get("sod_gas"));
  ASSERT_TRUE(m->fields().has(Field::peak_pressure));
  ParticleStore s;
  s.require(kEngineFields);
  s.require(m->fields());
  s.add_group(0, 2);
  for (std::size_t i = 0; i < 2; ++i) {
    s.col(Field::rho)[i] = 1.0;
    s.col(Field::energy)[i] = 2.5;
    s.col(Field::mass)[i] = 1.0;
  }
  m->initialise(s, {0, 2});
  EXPECT_EQ(s.col(Field::peak_pressure)[0], s.col(Field::pressure)[0]);  // starts at p0 = 1
  std::vector<double> running(2, s.col(Field::pressure)[0]);
  for (int step = 0; step < 20; ++step) {
    const double tr = step < 10 ? -0.02 : 0.02;
    for (std::size_t i = 0; i < 2; ++i) {
      // Point 1 is compressed half as much: the tracer is per point.
      const double t = i == 0 ? tr : 0.5 * tr;
      for (Field f : {Field::deps_xx, Field::deps_yy, Field::deps_zz}) s.col(f)[i] = t / 3;
      s.col(Field::rho)[i] /= 1.0 + t;
    }
    m->update(s, {0, 2}, {1e-3, 1e-2, {}});
    for (std::size_t i = 0; i < 2; ++i) {
      running[i] = std::max(running[i], s.col(Field::pressure)[i]);
      EXPECT_EQ(s.col(Field::peak_pressure)[i], running[i]) << step << " " << i;
    }
  }
  // After the release the pressure is back below the peak, which stays.
  EXPECT_LT(s.col(Field::pressure)[0], 0.9 * s.col(Field::peak_pressure)[0]);
  EXPECT_GT(s.col(Field::peak_pressure)[0], s.col(Field::peak_pressure)[1]);
}

}  // namespace
}  // namespace shatter
