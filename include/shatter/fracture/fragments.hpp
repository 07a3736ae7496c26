#pragma once
// Fragment search and kinematics (ISSUE fracture; MPM paper Sec. 4.1.2 and Eq. 20; BA95 Sec. 4.4).
// Implemented in src/fracture/.

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "shatter/core/particles.hpp"

namespace shatter {

struct FragmentSearchSpec {
  std::string method = "grid_density";  // grid_density (MPM paper) | friends_of_friends (BA95)
  double damage_threshold = 0.9;        // failed = D >= threshold
  double cell_size = 0.0;               // clustering grid; 0 = twice the mean particle spacing
};

struct Fragment {
  std::int64_t id = 0;  // 0 = largest
  std::size_t particles = 0;
  double mass = 0.0;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d momentum = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular_momentum = Eigen::Vector3d::Zero();  // about the centre of mass
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
  Eigen::Vector3d omega = Eigen::Vector3d::Zero();
  std::array<double, 3> axes{};  // a >= b >= c of the equivalent ellipsoid
  double volume = 0.0;
};

struct FragmentCatalogue {
  std::vector<Fragment> fragments;  // sorted by mass, largest first
  double dust_mass = 0.0;           // material below resolution (in no fragment)
  double total_mass = 0.0;
};

// Finds fragments; if the store has IField::fragment it is filled (-1 = dust).
FragmentCatalogue find_fragments(ParticleStore& store, const FragmentSearchSpec& spec);

void write_fragments_csv(const FragmentCatalogue& cat, const std::filesystem::path& file);
void write_fragments_hdf5(const FragmentCatalogue& cat, const std::filesystem::path& file);
// pkdgrav-style text: mass, radius of equal volume, position, velocity, spin per fragment.
void write_fragments_pkdgrav(const FragmentCatalogue& cat, const std::filesystem::path& file);

}  // namespace shatter
