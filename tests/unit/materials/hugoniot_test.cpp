// Material probe: EOS sampling and the principal Hugoniot (Rankine–Hugoniot jumps).

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "material_test_support.hpp"
#include "shatter/material/probe.hpp"

namespace shatter {
namespace {

// The jump conditions of every row. Mass and energy are imposed through rho(x) and E(x), so they
// hold to a few ulp (1e-13 relative); the momentum jump is the bisection residual at adjacent
// doubles of x, i.e. dp/dx * ulp(x) ~ p * 1e-15 * stiffness, so 1e-10 relative of p.
void expect_jumps(const std::vector<HugoniotRow>& rows, double rho0, double e0, double p0) {
  for (const auto& r : rows) {
    if (r.up == 0.0) continue;
    EXPECT_NEAR(rho0 * r.us, r.rho * (r.us - r.up), 1e-13 * rho0 * r.us) << r.up;
    EXPECT_NEAR(r.p - p0, rho0 * r.us * r.up, 1e-10 * std::abs(r.p) + 1e-6) << r.up;
    const double de = 0.5 * (r.p + p0) * (1.0 / rho0 - 1.0 / r.rho);
    EXPECT_NEAR(r.energy - e0, de, 1e-9 * std::abs(de) + 1e-9) << r.up;
    EXPECT_GT(r.us, r.up);
  }
}

TEST(Hugoniot, TillotsonBasaltSatisfiesJumpConditions) {
  const auto basalt = MaterialCatalogue::builtin().get("basalt");
  const auto rows = hugoniot(basalt, 8000.0, 33);
  ASSERT_EQ(rows.size(), 33u);
  expect_jumps(rows, 2700.0, 0.0, 0.0);
  // Acoustic limit: Us(0) = c_K = sqrt(A / rho0) at the reference state.
  EXPECT_NEAR(rows[0].us, std::sqrt(26.7e9 / 2700.0), 1e-9);
  // Compression increases along the Hugoniot.
  for (std::size_t k = 1; k < rows.size(); ++k) EXPECT_GT(rows[k].p, rows[k - 1].p);
}

TEST(Hugoniot, MieGruneisenReproducesItsLinearUsUp) {
  // On the reference Hugoniot the solution is exactly Us = c0 + s up (see mie_gruneisen.hpp),
  // so the probe must recover it to the bisection round-off (1e-9 relative).
  const auto al = MaterialCatalogue::builtin().get("aluminium_6061");
  const double ups[] = {100.0, 500.0, 1000.0, 2000.0, 3000.0};
  const auto rows = hugoniot(al, ups);
  for (const auto& r : rows) EXPECT_NEAR(r.us, 5240.0 + 1.4 * r.up, 1e-9 * r.us) << r.up;
  expect_jumps(rows, 2703.0, 0.0, 0.0);
}

TEST(Hugoniot, IdealGasStrongShockCompressionLimit) {
  // gamma = 1.4: compression tends to (gamma + 1)/(gamma - 1) = 6 for strong shocks; from a
  // reference state with p0 = 1 the jumps include p0 terms.
  const auto gas = MaterialCatalogue::builtin().get("sod_gas");
  const double ups[] = {0.5, 5.0, 500.0};
  const auto rows = hugoniot(gas, ups, {1.0, 2.5});
  expect_jumps(rows, 1.0, 2.5, 1.0);
  EXPECT_NEAR(rows.back().rho, 6.0, 1e-3);
}

TEST(EosProbe, ReportsRegionAndSpeeds) {
  const auto basalt = MaterialCatalogue::builtin().get("basalt");
  const auto s = probe_eos(basalt, 2500.0, 1e7);
  EXPECT_EQ(s.region, "mixed");
  EXPECT_GT(s.soundspeed, s.bulk_speed);  // Eq. 13 adds 4G/3rho
  EXPECT_EQ(probe_eos(basalt, 3000.0, 0.0).region, "compressed");
  EXPECT_EQ(probe_eos(MaterialCatalogue::builtin().get("sod_gas"), 1.0, 2.5).region, "ideal_gas");
}

TEST(ProbeWriters, CsvHasUnitsAndOneLinePerRow) {
  const auto rows = hugoniot(MaterialCatalogue::builtin().get("basalt"), 1000.0, 3);
  std::ostringstream csv, table;
  write_hugoniot_csv(csv, rows);
  write_hugoniot_table(table, rows);
  const std::string c = csv.str();
  EXPECT_EQ(c.substr(0, c.find('\n')), "up_m_per_s,us_m_per_s,p_Pa,rho_kg_per_m3,energy_J_per_kg");
  EXPECT_EQ(std::count(c.begin(), c.end(), '\n'), 4);
  EXPECT_NE(table.str().find("Us (m/s)"), std::string::npos);
}

}  // namespace
}  // namespace shatter
