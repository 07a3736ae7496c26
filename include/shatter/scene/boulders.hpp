#pragma once
// Random boulder fields (issue 32; docs/scenes.md, "Boulders"): non-overlapping spheres of a
// second material placed at random inside a host body, as Raducan et al. 2024 (Nature Astronomy
// 8) ran Dimorphos with and without boulders. The radii follow a truncated power law of the
// cumulative size-frequency distribution,
//
//   N(>r) proportional to r^-q,   radius_min <= r <= radius_max,
//
// the form in which boulder counts on asteroid surfaces are reported (Daly et al. 2023 and
// Pajola et al. 2024 give q for Didymos and Dimorphos). Radii are drawn until their volume
// reaches volume_fraction of the host's volume (inside the region, when one is given), sorted
// largest first, and each is placed by rejection sampling: a centre uniform in the host's
// bounds, kept when the sphere lies inside the host and the region and overlaps no boulder
// placed before it. The draw is a fixed generator (std::mt19937_64, whose sequence the C++
// standard fixes) with our own mapping of its bits to [0, 1), so the field is the same for a
// seed on every platform, thread and rank count.
//
// Axisymmetric (r-z) scenes fill the half-plane y = 0, r > 0 and revolve it: a boulder there is
// the disk of its radius in that half-plane, revolved, so a ring (torus) of volume
// 2 pi r_c pi r^2 about the axis, except a boulder centred on the axis, which is a sphere. A
// centre drawn nearer the axis than the boulder's radius is moved onto the axis (a disk across
// the axis sweeps neither a ring nor a sphere). Centres are uniform in the (r, z) half-plane, so
// the volume fraction is uniform in expectation.

#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include "shatter/scene/shapes.hpp"

namespace shatter::scene {

// A set of disjoint spheres with a uniform hash grid for the inside test (a boulder field of
// thousands of spheres is tested at every lattice point of its host).
class SphereSet {
 public:
  explicit SphereSet(double cell);
  void add(const Sphere& s);
  bool contains(const Vec3& p) const;
  // Whether `s` overlaps (or touches) a sphere of the set.
  bool overlaps(const Sphere& s) const;
  Bounds bounds() const { return bounds_; }
  const std::vector<Sphere>& spheres() const { return spheres_; }

 private:
  std::int64_t key(std::int64_t i, std::int64_t j, std::int64_t k) const;
  double cell_;
  std::vector<Sphere> spheres_;
  std::unordered_map<std::int64_t, std::vector<std::uint32_t>> grid_;
  Bounds bounds_;
};

struct BoulderParams {
  double volume_fraction = 0.0;  // of the host's volume (inside the region)
  double radius_min = 0.0;       // m
  double radius_max = 0.0;       // m
  double exponent = 0.0;         // q of N(>r) ~ r^-q (> 0)
  std::uint64_t seed = 1;
  std::optional<Bounds> region;  // boulders lie wholly inside it when given
  bool axisymmetric = false;     // r-z: rings about the z axis (see above)
  double spacing = 0.0;          // the host's point spacing: the volume is measured on its lattice
  std::string stream;            // mixed into the seed (the host's name): hosts differ
};

// What was placed: the spheres (centres at y = 0 in r-z), their volume (spheres, or rings in
// r-z) and the host's volume it is a fraction of.
struct BoulderField {
  std::shared_ptr<const SphereSet> set;
  double volume = 0.0;       // m^3 of boulders (exact sphere / ring volumes)
  double host_volume = 0.0;  // m^3 of host inside the region, measured on the host's lattice
  double fraction() const { return host_volume > 0.0 ? volume / host_volume : 0.0; }
};

// A placement that cannot be made; `key` is the boulders key it concerns.
struct BoulderError : std::runtime_error {
  BoulderError(std::string k, const std::string& message)
      : std::runtime_error(message), key(std::move(k)) {}
  std::string key;
};

// Volume of a boulder of radius r centred at c: a sphere, or in r-z a ring unless on the axis.
double boulder_volume(const Sphere& s, bool axisymmetric);

// Places the boulders inside `host` (throws BoulderError when the fraction cannot be reached).
BoulderField place_boulders(const Shape& host, const BoulderParams& p);

}  // namespace shatter::scene
