// Fragment tables: CSV, HDF5 and pkdgrav-style files read back, and the cumulative mass
// distribution.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <hdf5.h>

#include "shatter/fracture/fragments.hpp"

namespace shatter {
namespace {

FragmentCatalogue sample() {
  FragmentCatalogue cat;
  const double masses[] = {5.0, 2.0, 2.0, 0.5};
  for (int i = 0; i < 4; ++i) {
    Fragment f;
    f.id = i;
    f.particles = static_cast<std::size_t>(10 - i);
    f.mass = masses[i];
    f.centre = Eigen::Vector3d(i, 2.0 * i, -1.0);
    f.velocity = Eigen::Vector3d(0.25 * i, 0.0, 1.0);
    f.omega = Eigen::Vector3d(0.0, 0.0, 3.0 * i);
    f.volume = f.mass / 2700.0;
    cat.fragments.push_back(f);
    cat.total_mass += f.mass;
  }
  cat.dust_mass = 0.5;
  cat.total_mass += cat.dust_mass;
  return cat;
}

std::filesystem::path scratch(const char* name) {
  const auto dir = std::filesystem::temp_directory_path() / "shatter_fracture_test";
  std::filesystem::create_directories(dir);
  return dir / name;
}

std::vector<std::string> lines(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::vector<std::string> out;
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

TEST(FragmentOutput, CumulativeMassDistributionCountsFragmentsAtOrAboveEachMass) {
  // Masses 5, 2, 2, 0.5: N(>=5) = 1, N(>=2) = 3, N(>=0.5) = 4; exact.
  const auto c = cumulative_mass_distribution(sample());
  ASSERT_EQ(c.size(), 3U);
  EXPECT_EQ(c[0].count, 1U);
  EXPECT_EQ(c[1].mass, 2.0);
  EXPECT_EQ(c[1].count, 3U);
  EXPECT_EQ(c[1].cumulative_mass, 9.0);
  EXPECT_EQ(c[2].count, 4U);
  const auto file = scratch("cumulative.csv");
  write_cumulative_mass_csv(sample(), file);
  const auto l = lines(file);
  ASSERT_EQ(l.size(), 4U);
  EXPECT_EQ(l[0], "mass_kg,count_ge,cumulative_mass_kg,mass_over_total");
}

TEST(FragmentOutput, CsvHasUnitsInTheHeaderAndOneRowPerFragment) {
  const auto file = scratch("fragments.csv");
  write_fragments_csv(sample(), file);
  const auto l = lines(file);
  ASSERT_EQ(l.size(), 6U);  // comment, header, 4 fragments
  EXPECT_NE(l[1].find("id,particles,mass_kg,x_m,y_m,z_m,vx_m/s"), std::string::npos);
  EXPECT_EQ(l[3].substr(0, 6), "1,9,2,");  // id, particles, mass
}

TEST(FragmentOutput, Hdf5TablesReadBack) {
  const auto file = scratch("fragments.h5");
  write_fragments_hdf5(sample(), file);
  const hid_t h5 = H5Fopen(file.string().c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(h5, 0);
  const hid_t set = H5Dopen2(h5, "/fragments/mass", H5P_DEFAULT);
  ASSERT_GE(set, 0);
  std::vector<double> mass(4);
  ASSERT_GE(H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, mass.data()), 0);
  EXPECT_EQ(mass, (std::vector<double>{5.0, 2.0, 2.0, 0.5}));
  H5Dclose(set);
  const hid_t wz = H5Dopen2(h5, "/fragments/wz", H5P_DEFAULT);
  std::vector<double> spin(4);
  ASSERT_GE(H5Dread(wz, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, spin.data()), 0);
  EXPECT_EQ(spin[3], 9.0);
  H5Dclose(wz);
  EXPECT_GT(H5Lexists(h5, "/cumulative_mass/count_ge", H5P_DEFAULT), 0);
  H5Fclose(h5);
}

TEST(FragmentOutput, PkdgravRowsHoldMassRadiusPositionVelocitySpin) {
  // Radius of equal volume: (3 V / 4 pi)^(1/3) with V = 5 kg / 2700 kg/m^3 -> 7.6180e-2 m (hand
  // value to 5 digits, hence 1e-6).
  const auto file = scratch("fragments.pkd");
  write_fragments_pkdgrav(sample(), file);
  const auto l = lines(file);
  ASSERT_EQ(l.size(), 6U);
  std::istringstream row(l[2]);
  double v[12];
  for (double& x : v) row >> x;
  EXPECT_EQ(v[1], 5.0);
  EXPECT_NEAR(v[2], 7.6180e-2, 1e-6);
  EXPECT_EQ(v[8], 1.0);
}

}  // namespace
}  // namespace shatter
