// Random boulder fields (include/shatter/scene/boulders.hpp).

#include "shatter/scene/boulders.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <numbers>
#include <random>

#include <fmt/format.h>

#include "shatter/scene/lattice.hpp"

namespace shatter::scene {
namespace {

constexpr double kPi = std::numbers::pi;
// Tries per boulder before the placement gives up (a centre uniform in the host's bounds).
constexpr int kTries = 20000;
// Points on a boulder's surface tested against the host (and the centre).
constexpr int kSurfacePoints3 = 64;
constexpr int kSurfacePointsRz = 32;

// splitmix64 (Steele, Lea & Flood 2014): spreads a seed over all 64 bits.
std::uint64_t mix(std::uint64_t z) {
  z += 0x9E3779B97F4A7C15ULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

// FNV-1a of a name, so that two hosts with the same seed draw different fields.
std::uint64_t fnv1a(const std::string& s) {
  std::uint64_t h = 0xCBF29CE484222325ULL;
  for (unsigned char c : s) {
    h ^= c;
    h *= 0x100000001B3ULL;
  }
  return h;
}

// Uniform numbers in [0, 1) from the 53 high bits of mt19937_64 (std::uniform_real_distribution
// is not specified bit for bit, so it differs between standard libraries).
class Draw {
 public:
  explicit Draw(std::uint64_t seed) : gen_(seed) {}
  double uniform() { return static_cast<double>(gen_() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

 private:
  std::mt19937_64 gen_;
};

// A radius of the truncated power law N(>r) ~ r^-q on [r_min, r_max], by inverting its
// cumulative distribution: P(R > r) = (r^-q - r_max^-q) / (r_min^-q - r_max^-q).
double draw_radius(Draw& d, const BoulderParams& p) {
  if (p.radius_max <= p.radius_min) return p.radius_min;
  const double a = std::pow(p.radius_min, -p.exponent);
  const double b = std::pow(p.radius_max, -p.exponent);
  const double r = std::pow(a - d.uniform() * (a - b), -1.0 / p.exponent);
  return std::clamp(r, p.radius_min, p.radius_max);
}

bool in_region(const BoulderParams& p, const Vec3& x) {
  if (!p.region) return true;
  const Bounds& b = *p.region;
  if (p.axisymmetric) {  // the box bounds r by its x range and z by its z range
    return x.x() >= b.lo.x() && x.x() <= b.hi.x() && x.z() >= b.lo.z() && x.z() <= b.hi.z();
  }
  return (x.array() >= b.lo.array()).all() && (x.array() <= b.hi.array()).all();
}

// The host's volume inside the region, on the host's lattice (each point its cell, or in r-z its
// ring 2 pi r s^2).
double host_volume(const Shape& host, const BoulderParams& p) {
  const double s = p.spacing;
  double v = 0.0;
  if (p.axisymmetric) {
    for_each_lattice_point_rz(host, s, [&](const Vec3& x) {
      if (in_region(p, x)) v += 2.0 * kPi * x.x() * s * s;
    });
  } else {
    for_each_lattice_point(host, s, -1, [&](const Vec3& x) {
      if (in_region(p, x)) v += s * s * s;
    });
  }
  return v;
}

// Whether a boulder lies inside the host: its centre and points spread over its surface (a
// Fibonacci lattice on the sphere; in r-z a circle in the half-plane, reflected onto r >= 0).
bool inside_host(const Shape& host, const Sphere& b, bool rz) {
  auto in = [&](Vec3 x) {
    if (rz) x.x() = std::abs(x.x());
    return host.contains(x);
  };
  if (!in(b.centre)) return false;
  if (rz) {
    for (int i = 0; i < kSurfacePointsRz; ++i) {
      const double t = 2.0 * kPi * i / kSurfacePointsRz;
      if (!in(b.centre + b.radius * Vec3(std::cos(t), 0.0, std::sin(t)))) return false;
    }
    return true;
  }
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < kSurfacePoints3; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / kSurfacePoints3;
    const double rho = std::sqrt(1.0 - z * z), t = golden * i;
    if (!in(b.centre + b.radius * Vec3(rho * std::cos(t), rho * std::sin(t), z))) return false;
  }
  return true;
}

// Where centres are drawn: the host's bounds within the region (in r-z: r from the axis or the
// region's inner r, to the host's radial extent).
Bounds centre_box(const Shape& host, const BoulderParams& p) {
  Bounds b = host.bounds();
  if (p.axisymmetric) {
    const double r =
        std::max({std::abs(b.lo.x()), std::abs(b.hi.x()), std::abs(b.lo.y()), std::abs(b.hi.y())});
    b.lo.x() = 0.0;
    b.hi.x() = r;
    b.lo.y() = b.hi.y() = 0.0;
  }
  if (p.region) {
    b.lo = b.lo.cwiseMax(p.region->lo);
    b.hi = b.hi.cwiseMin(p.region->hi);
    if (p.axisymmetric) b.lo.y() = b.hi.y() = 0.0;
  }
  return b;
}

// A centre for a boulder of radius r, or none when the box is too small for it.
std::optional<Vec3> draw_centre(Draw& d, const Bounds& box, double r, const BoulderParams& p) {
  Vec3 c = Vec3::Zero();
  for (int a = 0; a < 3; ++a) {
    if (p.axisymmetric && a == 1) continue;
    // On the axis (r-z, box from r = 0) a boulder is a sphere: its centre may lie at r = 0.
    const bool axis = p.axisymmetric && a == 0 && box.lo.x() <= 0.0;
    const double lo = axis ? 0.0 : box.lo[a] + r, hi = box.hi[a] - r;
    if (hi < lo) return std::nullopt;
    c[a] = d.uniform(lo, hi);
  }
  // r-z: a disk across the axis sweeps neither a ring nor a sphere; moved onto the axis.
  if (p.axisymmetric && c.x() < r) c.x() = 0.0;
  return c;
}

// Calls f(i, j, k) for every bucket cell the sphere's bounding box touches, until f returns true;
// returns whether one did.
template <class F>
bool for_each_cell(const Sphere& s, double cell, F&& f) {
  std::array<std::int64_t, 3> a{}, b{};
  for (int d = 0; d < 3; ++d) {
    a[d] = static_cast<std::int64_t>(std::floor((s.centre[d] - s.radius) / cell));
    b[d] = static_cast<std::int64_t>(std::floor((s.centre[d] + s.radius) / cell));
  }
  for (std::int64_t k = a[2]; k <= b[2]; ++k) {
    for (std::int64_t j = a[1]; j <= b[1]; ++j) {
      for (std::int64_t i = a[0]; i <= b[0]; ++i) {
        if (f(i, j, k)) return true;
      }
    }
  }
  return false;
}

}  // namespace

SphereSet::SphereSet(double cell) : cell_(cell) {}

std::int64_t SphereSet::key(std::int64_t i, std::int64_t j, std::int64_t k) const {
  // Buckets may share a key: the tests below compare distances, so a shared bucket costs time only.
  return (i * 73856093LL) ^ (j * 19349663LL) ^ (k * 83492791LL);
}

void SphereSet::add(const Sphere& s) {
  const auto id = static_cast<std::uint32_t>(spheres_.size());
  spheres_.push_back(s);
  const Vec3 lo = s.centre.array() - s.radius, hi = s.centre.array() + s.radius;
  if (id == 0) {
    bounds_ = {lo, hi};
  } else {
    bounds_.lo = bounds_.lo.cwiseMin(lo);
    bounds_.hi = bounds_.hi.cwiseMax(hi);
  }
  for_each_cell(s, cell_, [&](std::int64_t i, std::int64_t j, std::int64_t k) {
    auto& bucket = grid_[key(i, j, k)];
    if (bucket.empty() || bucket.back() != id) bucket.push_back(id);
    return false;
  });
}

bool SphereSet::contains(const Vec3& p) const {
  const auto it = grid_.find(key(static_cast<std::int64_t>(std::floor(p.x() / cell_)),
                                 static_cast<std::int64_t>(std::floor(p.y() / cell_)),
                                 static_cast<std::int64_t>(std::floor(p.z() / cell_))));
  if (it == grid_.end()) return false;
  for (const std::uint32_t id : it->second) {
    const Sphere& s = spheres_[id];
    if ((p - s.centre).squaredNorm() < s.radius * s.radius) return true;
  }
  return false;
}

bool SphereSet::overlaps(const Sphere& s) const {
  return for_each_cell(s, cell_, [&](std::int64_t i, std::int64_t j, std::int64_t k) {
    const auto it = grid_.find(key(i, j, k));
    if (it == grid_.end()) return false;
    for (const std::uint32_t id : it->second) {
      const Sphere& o = spheres_[id];
      const double r = o.radius + s.radius;
      if ((o.centre - s.centre).squaredNorm() <= r * r) return true;
    }
    return false;
  });
}

double boulder_volume(const Sphere& s, bool axisymmetric) {
  const double r = s.radius;
  if (axisymmetric && s.centre.x() > 0.0) return 2.0 * kPi * s.centre.x() * kPi * r * r;  // Pappus
  return 4.0 / 3.0 * kPi * r * r * r;
}

BoulderField place_boulders(const Shape& host, const BoulderParams& p) {
  BoulderField field;
  field.host_volume = host_volume(host, p);
  if (!(field.host_volume > 0.0)) {
    throw BoulderError(p.region ? "region_lo" : "volume_fraction",
                       "the host has no volume inside the region (no lattice point of it lies "
                       "there)");
  }
  const Bounds box = centre_box(host, p);
  for (int a = 0; a < 3; ++a) {
    if (p.axisymmetric && a == 1) continue;
    const double room = p.axisymmetric && a == 0 && box.lo.x() <= 0.0
                            ? box.hi.x() - box.lo.x()
                            : 0.5 * (box.hi[a] - box.lo[a]);
    if (p.radius_max > room) {
      throw BoulderError(
          "radius_max",
          fmt::format("= {} m does not fit in the host{} ({:.4g} m across on {})", p.radius_max,
                      p.region ? " inside the region" : "", 2.0 * room,
                      p.axisymmetric && a == 0 ? std::string("r") : std::string(1, "xyz"[a])));
    }
  }
  auto set = std::make_shared<SphereSet>(p.radius_max);
  Draw d(mix(p.seed ^ fnv1a(p.stream)));
  const double target = p.volume_fraction * field.host_volume;
  // r-z: the mean ring volume of a boulder of radius r, for the size of a draw (centres are
  // uniform in r, so the mean r_c is the middle of the r range).
  const double r_mean = 0.5 * (box.lo.x() + box.hi.x());
  auto expected = [&](double r) {
    return p.axisymmetric ? 2.0 * kPi * r_mean * kPi * r * r : 4.0 / 3.0 * kPi * r * r * r;
  };
  // Radii are drawn until their expected volume covers what is missing, then placed largest
  // first; in r-z a boulder's volume depends on where it lands, so further draws may follow.
  for (int round = 0; field.volume < target; ++round) {
    if (round == 1000) {
      throw BoulderError("volume_fraction", "the placement did not converge (1000 draws)");
    }
    std::vector<double> radii;
    for (double e = 0.0; e < target - field.volume;) {
      radii.push_back(draw_radius(d, p));
      e += expected(radii.back());
    }
    std::sort(radii.begin(), radii.end(), std::greater<>());
    for (const double r : radii) {
      bool placed = false;
      for (int t = 0; t < kTries && !placed; ++t) {
        const auto c = draw_centre(d, box, r, p);
        if (!c) break;
        const Sphere s{*c, r};
        if (set->overlaps(s) || !inside_host(host, s, p.axisymmetric)) continue;
        set->add(s);
        field.volume += boulder_volume(s, p.axisymmetric);
        placed = true;
      }
      if (!placed) {
        throw BoulderError(
            "volume_fraction",
            fmt::format("= {} cannot be reached: after {} boulders (fraction {:.4g}) a boulder of "
                        "radius {:.4g} m found no free place in {} tries; lower volume_fraction "
                        "or radius_max (random placement of equal spheres jams near 0.38)",
                        p.volume_fraction, set->spheres().size(), field.volume / field.host_volume,
                        r, kTries));
      }
      if (field.volume >= target) break;
    }
  }
  field.set = std::move(set);
  return field;
}

}  // namespace shatter::scene
