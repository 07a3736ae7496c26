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

// Radius of an ss record (pkdgrav hand-off, below): equal_volume, the sphere of the fragment's
// (or point's) volume; or packing_safe, the smaller of that and half the distance to the nearest
// other record, so that no two spheres overlap (r_i + r_j <= |x_i - x_j|), as pkdgrav's
// collision search expects of its initial conditions.
enum class SsRadius { equal_volume, packing_safe };

struct FragmentSearchSpec {
  std::string method = "grid_density";  // grid_density (MPM paper) | friends_of_friends (BA95)
  double damage_threshold = 0.9;        // failed = D >= threshold
  double cell_size = 0.0;               // clustering grid; 0 = twice the mean particle spacing
  // Two points are neighbours (friends) when closer than this; 0 = 1.5 x the mean particle
  // spacing, which links face and edge neighbours of a cubic lattice but not body diagonals.
  // Must not exceed cell_size (neighbours are searched in the 27 surrounding cells).
  double linking_length = 0.0;
  // grid_density: an unfailed point is extendable when the unfailed material in its cell fills
  // at least this fraction of the cell (sum of unfailed volume0 / cell volume; with 2x2x2 points
  // per cell, 0.5 = at least 4 unfailed points).
  double extendable_ratio = 0.5;
  // friends_of_friends: BA95's pre-pass, Pa; > 0 treats unfailed points whose largest principal
  // stress reaches it as failed (the store's damage column is not modified). Needs the stress.
  double static_strength = 0.0;
  // friends_of_friends: > 0 replaces linking_length by the SPH smoothing length, as BA95
  // Sec. 4.4 define friends ("a particle within one smoothing length"): i and j are friends when
  // closer than (h_i + h_j) / 2, h = smoothing_factor (mass / rho)^{1/3} (the SPH solver's rule,
  // so the factor is solver.sph.h_factor). Needs mass and rho; cell_size grows to max h if needed.
  double smoothing_factor = 0.0;
  // The pkdgrav hand-off's radius (the run passes only this spec to the report, so the choice of
  // output.ss_radius travels with it).
  SsRadius ss_radius = SsRadius::equal_volume;
  // r-z (solver.geometry = "axisymmetric", issue 31): each point is a ring about z in the
  // half-plane y = 0, r = x. The search links the rings in the half-plane by their cross-sections
  // (area A = (m / rho) / (2 pi r), spacing sqrt(mean A), cells of area h^2) and reports each
  // fragment as the body of revolution its rings sweep (fragment_kinematics, below).
  bool axisymmetric = false;
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
  // Composition (add_composition): mass from each body and each material, kg, indexed as the
  // catalogue's body_names and material_names; empty until computed.
  std::vector<double> mass_by_body;
  std::vector<double> mass_by_material;
  // Volume of the solid matrix, sum of v_p / alpha_p over a porous body's points (distension
  // alpha = rho_s / rho, issue 29), m^3; equal to volume for dense points (add_composition).
  double matrix_volume = 0.0;
  // r-z only (FragmentSearchSpec::axisymmetric): the radial extent of the fragment's rings, m, and
  // whether it touches the axis (a ring within one point spacing of it). A fragment off the axis
  // is a ring or torus: r-z cannot resolve its azimuthal break-up (no azimuthal structure).
  bool touches_axis = false;
  double r_min = 0.0;
  double r_max = 0.0;
};

struct FragmentCatalogue {
  std::vector<Fragment> fragments;  // sorted by mass, largest first
  double dust_mass = 0.0;           // material below resolution (in no fragment)
  double total_mass = 0.0;
  std::vector<std::string> body_names;      // composition columns; empty = no composition
  std::vector<std::string> material_names;  // distinct, in order of first use by a body
  bool axisymmetric = false;                // r-z: fragments are bodies of revolution about z
};

// Finds fragments; if the store has IField::fragment it is filled (-1 = dust). The result does
// not depend on particle order when the store has IField::id (ties are broken by id).
FragmentCatalogue find_fragments(ParticleStore& store, const FragmentSearchSpec& spec);

// Fragment label per particle (-1 = dust), numbered by discovery; the step before kinematics.
std::vector<std::int64_t> label_fragments(const ParticleStore& store,
                                          const FragmentSearchSpec& spec);

// Kinematics (MPM paper Eq. 20) of labelled particles; fragments sorted by mass, ids = rank.
// On return labels hold the rank ids. With `axisymmetric` (r-z rings) each fragment is the body
// of revolution of its rings: centre and velocity on the z axis (a ring's momentum is along z),
// no spin (v_theta = 0), the inertia of the revolved mass, touches_axis and r_min / r_max.
FragmentCatalogue fragment_kinematics(const ParticleStore& store, std::vector<std::int64_t>& labels,
                                      bool axisymmetric = false);

// Cumulative mass distribution: for each distinct fragment mass m (descending), the number of
// fragments with mass >= m and their summed mass.
struct CumulativePoint {
  double mass = 0.0;
  std::size_t count = 0;
  double cumulative_mass = 0.0;
};
std::vector<CumulativePoint> cumulative_mass_distribution(const FragmentCatalogue& cat);

void write_fragments_csv(const FragmentCatalogue& cat, const std::filesystem::path& file);
void write_fragments_hdf5(const FragmentCatalogue& cat, const std::filesystem::path& file);
// Mass of each fragment from each body and material. `store` holds the fragment labels
// (IField::fragment, as find_fragments leaves them) and IField::body; body b is made of
// material body_materials[b]. Throws std::invalid_argument when a body has no name.
void add_composition(FragmentCatalogue& cat, const ParticleStore& store,
                     const std::vector<std::string>& body_names,
                     const std::vector<std::string>& body_materials);

// pkdgrav's binary "ss" format (ssio.h of pkdgrav, D. C. Richardson 1998; e.g. the copy in
// N-BodyShop/gasoline): XDR (big-endian), a 16-byte header {double time; int n_data; int pad}
// (pad = -1, which newer ssio versions read as SSIO_MAGIC_STANDARD) and 96-byte records {double
// mass, radius, pos[3], vel[3], spin[3]; int color, org_idx}, in pkdgrav units: G = 1, length
// 1 AU, mass 1 solar mass, time 1 yr / 2 pi (docs/outputs.md, "N-body hand-off").
struct SsRecord {  // SI units
  double mass = 0.0;
  double radius = 0.0;
  Eigen::Vector3d pos = Eigen::Vector3d::Zero();
  Eigen::Vector3d vel = Eigen::Vector3d::Zero();
  Eigen::Vector3d spin = Eigen::Vector3d::Zero();
  std::int32_t color = 0;
  std::int32_t org_idx = 0;
};
struct SsFile {
  double time = 0.0;  // s
  std::vector<SsRecord> records;
};
namespace pkdgrav_units {
inline constexpr double kLength = 1.495978707e11;  // m, the astronomical unit (IAU 2012)
inline constexpr double kGM = 1.32712440018e20;    // m^3/s^2, heliocentric GM (IAU 2009)
inline constexpr double kG = 6.67430e-11;          // m^3/(kg s^2), CODATA 2018
inline constexpr double kMass = kGM / kG;          // kg: G = 1 with this mass unit
double time();                                     // s, sqrt(AU^3 / GM) ~ 1 yr / 2 pi
}  // namespace pkdgrav_units
void write_ss(const SsFile& ss, const std::filesystem::path& file);
SsFile read_ss(const std::filesystem::path& file);  // throws naming the file when malformed
// Colours in ss files: a palette from tipsy's colour table, 3, 4, 8, 9, 10, 12, 13, 14, 15,
// free of the colours ssdefs.h reserves for the Sun and the planets (5, 2, 11, 6, 7); body b
// (or fragment b) gets palette[b mod 9], so colours stay in 3..15 however many there are. Dust
// (a point in no fragment) is 1.
inline constexpr std::int32_t kSsDustColour = 1;
std::int32_t ss_body_colour(std::int64_t body);
std::int32_t ss_fragment_colour(std::int64_t fragment);
const std::vector<std::int32_t>& ss_palette();
SsRadius ss_radius_by_name(const std::string& name);  // throws naming the allowed values
// Shrinks each record's radius to at most half its nearest-neighbour distance; returns how many
// were shrunk.
std::size_t apply_packing_safe_radius(SsFile& ss);
// One record per fragment: mass, radius (equal volume unless packing_safe), centre, velocity,
// spin; colour = the body giving most of its mass (needs add_composition; else body 0's),
// org_idx = fragment id.
SsFile fragments_ss(const FragmentCatalogue& cat, double time,
                    SsRadius radius = SsRadius::equal_volume);
// One record per particle (every point still in the simulation, for rubble-pile
// reaccumulation): radius of its volume (mass / rho) unless packing_safe, colour = its fragment
// (dust 1), org_idx = its index. Needs mass, rho, positions, velocities and IField::fragment.
SsFile particles_ss(const ParticleStore& store, double time,
                    SsRadius radius = SsRadius::equal_volume);
void write_cumulative_mass_csv(const FragmentCatalogue& cat, const std::filesystem::path& file);

}  // namespace shatter
