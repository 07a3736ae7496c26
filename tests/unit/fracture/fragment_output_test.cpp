// Fragment tables: CSV, HDF5 and pkdgrav ss files read back, fragment composition, and the
// cumulative mass distribution.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
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

TEST(FragmentOutput, SsFileHasPkdgravsBigEndianLayoutAndUnits) {
  // ssio.h: 16-byte header {double time; int n_data; int pad}, 96-byte records, XDR big-endian.
  auto cat = sample();
  const auto file = scratch("fragments.ss");
  write_ss(fragments_ss(cat, 0.0), file);
  std::ifstream in(file, std::ios::binary);
  const std::string b((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_EQ(b.size(), 16U + 4U * 96U);
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(b[k]); };
  for (std::size_t k = 0; k < 8; ++k) EXPECT_EQ(byte(k), 0U) << k;  // time 0.0
  EXPECT_EQ(byte(11), 4U);                                          // n_data = 4, big-endian
  EXPECT_EQ(byte(12), 0xffU);                                       // pad = -1 (magic)
  // The first record's mass: 5 kg / M_sun (M_sun = GM_sun / G = 1.98841e30 kg) = 2.5146e-30,
  // whose binary64 exponent byte pair is 0x39 0xc9 (hand-encoded from the value).
  EXPECT_EQ(byte(16), 0x39U);
  EXPECT_EQ(byte(17), 0xc9U);
}

TEST(FragmentOutput, SsRoundTripRestoresSiValuesColoursAndIds) {
  // Unit conversion both ways: relative error of one binary64 rounding per factor, 1e-14.
  auto cat = sample();
  cat.fragments[1].mass_by_body = {0.5, 1.5};  // body 1 dominates: colour 4
  const auto file = scratch("fragments_rt.ss");
  write_ss(fragments_ss(cat, 2.5e-4), file);
  const SsFile back = read_ss(file);
  EXPECT_NEAR(back.time, 2.5e-4, 1e-14 * 2.5e-4);
  ASSERT_EQ(back.records.size(), 4U);
  for (std::size_t i = 0; i < 4; ++i) {
    const Fragment& f = cat.fragments[i];
    const SsRecord& r = back.records[i];
    EXPECT_NEAR(r.mass, f.mass, 1e-14 * f.mass);
    EXPECT_NEAR(r.radius, std::cbrt(3.0 * f.volume / (4.0 * std::numbers::pi)), 1e-14);
    EXPECT_NEAR((r.pos - f.centre).norm(), 0.0, 1e-14 * (1.0 + f.centre.norm()));
    EXPECT_NEAR((r.vel - f.velocity).norm(), 0.0, 1e-14 * (1.0 + f.velocity.norm()));
    EXPECT_NEAR((r.spin - f.omega).norm(), 0.0, 1e-14 * (1.0 + f.omega.norm()));
    EXPECT_EQ(r.org_idx, static_cast<std::int32_t>(i));
  }
  EXPECT_EQ(back.records[0].color, 3);  // no composition: body 0's colour
  EXPECT_EQ(back.records[1].color, 4);
  // pkdgrav's time unit is a year / 2 pi: sqrt(AU^3 / GM_sun) = 5.0226e6 s (to 5 digits).
  EXPECT_NEAR(pkdgrav_units::time(), 5.0226e6, 1e2);
}

TEST(FragmentOutput, TruncatedSsFileIsRefusedByName) {
  const auto file = scratch("short.ss");
  write_ss(fragments_ss(sample(), 0.0), file);
  std::filesystem::resize_file(file, 16 + 96 + 10);
  try {
    read_ss(file);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("short.ss"), std::string::npos) << e.what();
  }
}

TEST(FragmentOutput, CompositionSumsMassPerBodyAndMaterialIntoTheTables) {
  // Three points: fragment 0 = body 0 (1 kg) + body 1 (2 kg); body 2 shares body 0's material.
  ParticleStore store;
  store.require(FieldSet{Field::mass});
  store.require(IField::fragment);
  store.require(IField::body);
  store.add_group(0, 4);
  const double m[] = {1.0, 2.0, 4.0, 8.0};
  const std::int64_t frag[] = {0, 0, 1, -1}, body[] = {0, 1, 2, 2};
  for (std::size_t p = 0; p < 4; ++p) {
    store.col(Field::mass)[p] = m[p];
    store.col(IField::fragment)[p] = frag[p];
    store.col(IField::body)[p] = body[p];
  }
  FragmentCatalogue cat;
  cat.fragments.resize(2);
  cat.fragments[0].mass = 3.0;
  cat.fragments[1].id = 1;
  cat.fragments[1].mass = 4.0;
  add_composition(cat, store, {"target", "projectile", "moon"}, {"basalt", "nylon", "basalt"});
  ASSERT_EQ(cat.material_names, (std::vector<std::string>{"basalt", "nylon"}));
  EXPECT_EQ(cat.fragments[0].mass_by_body, (std::vector<double>{1.0, 2.0, 0.0}));
  EXPECT_EQ(cat.fragments[0].mass_by_material, (std::vector<double>{1.0, 2.0}));
  EXPECT_EQ(cat.fragments[1].mass_by_material, (std::vector<double>{4.0, 0.0}));
  const auto file = scratch("composition.csv");
  write_fragments_csv(cat, file);
  const auto l = lines(file);
  EXPECT_NE(l[1].find(",mass_body_target_kg,mass_body_projectile_kg,mass_body_moon_kg,"
                      "mass_material_basalt_kg,mass_material_nylon_kg"),
            std::string::npos)
      << l[1];
  EXPECT_NE(l[2].rfind(",1,2,0,1,2"), std::string::npos) << l[2];
}

// Issue 29: a porous fragment's bulk density (pores included) and its matrix density (mass over
// sum m / (alpha rho)); a dense point (no distension: 0 in the column) counts with alpha = 1.
TEST(FragmentOutput, PorousFragmentsGiveBulkAndMatrixDensity) {
  ParticleStore store;
  store.require(FieldSet{Field::mass, Field::rho, Field::distension});
  store.require(IField::fragment);
  store.require(IField::body);
  store.add_group(0, 3);
  // fragment 0: two porous points (alpha 2 and 1.5 at bulk 1350 and 1800: matrix 2700 each);
  // fragment 1: one dense point at 2700 (distension 0: a dense material's).
  const double m[] = {1.0, 3.0, 2.0}, rho[] = {1350.0, 1800.0, 2700.0}, alpha[] = {2.0, 1.5, 0.0};
  for (std::size_t p = 0; p < 3; ++p) {
    store.col(Field::mass)[p] = m[p];
    store.col(Field::rho)[p] = rho[p];
    store.col(Field::distension)[p] = alpha[p];
    store.col(IField::fragment)[p] = p < 2 ? 0 : 1;
    store.col(IField::body)[p] = p < 2 ? 0 : 1;
  }
  FragmentCatalogue cat;
  cat.fragments.resize(2);
  cat.fragments[0].mass = 4.0;
  cat.fragments[0].volume = 1.0 / 1350.0 + 3.0 / 1800.0;  // as fragment_kinematics sums it
  cat.fragments[1].id = 1;
  cat.fragments[1].mass = 2.0;
  cat.fragments[1].volume = 2.0 / 2700.0;
  add_composition(cat, store, {"target", "projectile"}, {"pumice", "basalt"});
  // matrix volume 1/2700 + 3/2700: matrix density 2700 to rounding
  EXPECT_NEAR(cat.fragments[0].matrix_volume, 4.0 / 2700.0, 1e-18);
  EXPECT_NEAR(cat.fragments[1].matrix_volume, 2.0 / 2700.0, 1e-18);
  const auto file = scratch("porous.csv");
  write_fragments_csv(cat, file);
  const auto l = lines(file);
  const std::string head = l[1];
  auto column = [&](const std::string& row, const std::string& name) {
    std::size_t col = 0;
    for (std::size_t at = 0; at < head.find(name); ++at) col += head[at] == ',' ? 1 : 0;
    std::stringstream ss(row);
    std::string v;
    for (std::size_t k = 0; k <= col; ++k) std::getline(ss, v, ',');
    return std::stod(v);
  };
  ASSERT_NE(head.find("bulk_density_kg/m^3"), std::string::npos) << head;
  ASSERT_NE(head.find("matrix_density_kg/m^3"), std::string::npos) << head;
  // bulk 4 kg / (1/1350 + 3/1800) m^3 = 1661.54 kg/m^3; matrix 2700 (a few ulps: 1e-9 relative)
  EXPECT_NEAR(column(l[2], "bulk_density"), 4.0 / (1.0 / 1350.0 + 3.0 / 1800.0), 1e-9);
  EXPECT_NEAR(column(l[2], "matrix_density"), 2700.0, 1e-9);
  EXPECT_NEAR(column(l[3], "bulk_density"), 2700.0, 1e-9);
  EXPECT_NEAR(column(l[3], "matrix_density"), 2700.0, 1e-9);
}

}  // namespace
}  // namespace shatter
