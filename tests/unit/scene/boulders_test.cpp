// Random boulder fields, [body.NAME.boulders] (issue 32; include/shatter/scene/boulders.hpp): the
// field is a function of the seed, reaches the volume fraction asked, its spheres are disjoint
// and inside the host, the host and its boulder body split the host's lattice points exactly (so
// the mass is the host's alone), in 3-D and r-z; bad keys are refused naming key and line.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>
#include <tuple>

#include "scene_fixture.hpp"
#include "shatter/scene/boulders.hpp"
#include "shatter/scene/build.hpp"

namespace shatter::scene {
namespace {

using test::error_of;
using test::expect_names;
using test::line_of;
using test::parse;
using test::with;

// A 1 m cube of basalt with 2 cm to 7.5 cm boulders of basalt (the same material: the mass test).
const std::string kHost = R"(name = "boulders"

[solver]
cell_size = 0.05
end_time = 1.0e-6

[domain]
lo = [-0.6, -0.6, -0.6]
hi = [0.6, 0.6, 0.6]

[body.rock]
shape = "box"
lo = [-0.5, -0.5, -0.5]
hi = [0.5, 0.5, 0.5]
material = "basalt"
)";
const std::string kField = R"(
[body.rock.boulders]
material = "basalt"
volume_fraction = 0.2
radius_min = 0.025
radius_max = 0.075
exponent = 2.5
)";
const std::string kScene = kHost + kField;

// The same in r-z: a cylinder about the axis, 1 m across and 0.6 m deep.
const std::string kHostRz = R"(name = "boulders_rz"

[solver]
geometry = "axisymmetric"
shape = "bspline2"
cell_size = 0.05
end_time = 1.0e-6

[domain]
lo = [0.0, -0.7, -0.7]
hi = [0.7, 0.7, 0.1]

[body.rock]
shape = "cylinder"
centre = [0.0, 0.0, -0.3]
axis = [0.0, 0.0, 1.0]
radius = 0.5
length = 0.6
material = "basalt"
)";
const std::string kSceneRz = kHostRz + kField;

const BodySpec& body(const Scene& s, const std::string& name) {
  const auto it = std::find_if(s.bodies.begin(), s.bodies.end(),
                               [&](const BodySpec& b) { return b.name == name; });
  EXPECT_NE(it, s.bodies.end()) << name;
  return *it;
}

const std::vector<Sphere>& spheres(const Scene& s) {
  return body(s, "rock").shape.holes->spheres();
}

using Key = std::tuple<long, long, long>;
std::set<Key> lattice_keys(const std::vector<Vec3>& pts, double s) {
  std::set<Key> k;
  for (const Vec3& p : pts) {
    k.emplace(std::lround(p.x() / s * 2), std::lround(p.y() / s * 2), std::lround(p.z() / s * 2));
  }
  return k;
}

double total_mass(const Scene& s) {
  const BuiltScene b = build(s);
  const auto mass = b.particles.col(Field::mass);
  double m = 0.0;
  for (std::size_t p = 0; p < mass.size(); ++p) m += mass[p];
  return m;
}

TEST(Boulders, SameSeedSameFieldOtherSeedOther) {
  const Scene a = parse(kScene), b = parse(kScene);
  ASSERT_EQ(spheres(a).size(), spheres(b).size());
  for (std::size_t i = 0; i < spheres(a).size(); ++i) {
    EXPECT_EQ(spheres(a)[i].centre, spheres(b)[i].centre);
    EXPECT_EQ(spheres(a)[i].radius, spheres(b)[i].radius);
  }
  // The seed defaults to fracture.seed (what tools/study.py --seeds sets) ...
  const Scene c = parse(kScene, {"fracture.seed=2"});
  EXPECT_NE(spheres(a).front().centre, spheres(c).front().centre);
  // ... and the table's own seed wins over it.
  const Scene d = parse(kScene, {"fracture.seed=2", "body.rock.boulders.seed=1"});
  EXPECT_EQ(spheres(a).front().centre, spheres(d).front().centre);
  // The resolved scene carries what was placed.
  EXPECT_NE(a.resolved.find("placed = " + std::to_string(spheres(a).size())), std::string::npos)
      << a.resolved;
  EXPECT_NE(a.resolved.find("fraction_placed"), std::string::npos);
  // A run's scene.toml (the resolved scene) gives the same field again, whatever the fracture
  // seed then (its boulders' seed is written out): a resumed run has the same boulders.
  const Scene r = parse(a.resolved, {"fracture.seed=5"});
  ASSERT_EQ(spheres(r).size(), spheres(a).size());
  EXPECT_EQ(spheres(r).back().centre, spheres(a).back().centre);
  ASSERT_EQ(a.notes.size(), 1u);
  EXPECT_NE(a.notes[0].find("boulders"), std::string::npos);
}

// Largest first, disjoint, inside the host, radii within the range, and the volume fraction:
// the spheres' volume is at or above the fraction asked by less than one largest boulder; on
// the lattice (the boulder body's points) within 0.01 of it.
void expect_field(const Scene& s, bool rz) {
  const auto& sp = spheres(s);
  ASSERT_GT(sp.size(), 10u);
  const BodySpec& host = body(s, "rock");
  const BodySpec& field = body(s, "rock_boulders");
  double volume = 0.0;
  for (std::size_t i = 0; i < sp.size(); ++i) {
    EXPECT_GE(sp[i].radius, 0.025);
    EXPECT_LE(sp[i].radius, 0.075);
    if (rz) {
      EXPECT_EQ(sp[i].centre.y(), 0.0);
      EXPECT_TRUE(sp[i].centre.x() == 0.0 || sp[i].centre.x() >= sp[i].radius) << i;
    }
    volume += boulder_volume(sp[i], rz);
    for (std::size_t j = i + 1; j < sp.size(); ++j) {
      EXPECT_GT((sp[i].centre - sp[j].centre).norm(), sp[i].radius + sp[j].radius) << i << j;
    }
  }
  const double host_volume = host.fill.volume + field.fill.volume;
  const double vmax = rz ? 2.0 * std::numbers::pi * 0.5 * std::numbers::pi * 0.075 * 0.075
                         : 4.0 / 3.0 * std::numbers::pi * std::pow(0.075, 3);
  EXPECT_GE(volume / host_volume, 0.2 - 0.002);
  EXPECT_LE(volume / host_volume, 0.2 + vmax / host_volume + 0.002);
  EXPECT_NEAR(field.fill.volume / host_volume, 0.2, 0.01);
  for (const Vec3& p : field.fill.points) {
    EXPECT_TRUE(host.shape.parts.size() == 1 && contains(host.shape.parts[0], p));
  }
}

TEST(Boulders, DisjointInsideAndReachTheFraction) {
  expect_field(parse(kScene), false);
  expect_field(parse(kScene, {"fracture.seed=7"}), false);
}

TEST(Boulders, AxisymmetricRingsReachTheFraction) {
  expect_field(parse(kSceneRz), true);
  expect_field(parse(kSceneRz, {"fracture.seed=3"}), true);
}

// The host and its boulders hold exactly the host alone's lattice points, and its mass.
void expect_split(const std::string& host_only, const std::string& with_field) {
  const Scene alone = parse(host_only), s = parse(with_field);
  const BodySpec& h = body(s, "rock");
  const BodySpec& f = body(s, "rock_boulders");
  EXPECT_GT(f.fill.points.size(), 100u);
  std::vector<Vec3> both = h.fill.points;
  both.insert(both.end(), f.fill.points.begin(), f.fill.points.end());
  const auto k = lattice_keys(both, h.spacing);
  EXPECT_EQ(k.size(), both.size());  // no point in both bodies
  EXPECT_EQ(k, lattice_keys(body(alone, "rock").fill.points, h.spacing));
  const double m0 = total_mass(alone), m = total_mass(s);
  EXPECT_NEAR(m / m0, 1.0, 2e-3);
}

TEST(Boulders, HostAndBouldersSplitTheHostsPointsAndMass) {
  expect_split(kHost, kScene);
  expect_split(kHostRz, kSceneRz);
}

TEST(Boulders, SphWithBoulders) {
  // The fill is shared: an SPH scene gets the same two bodies.
  const Scene s = parse(with("end_time = 1.0e-6", "end_time = 1.0e-6\nmethod = \"sph\"", kScene));
  EXPECT_EQ(s.method, "sph");
  EXPECT_EQ(s.bodies.size(), 2u);
  EXPECT_GT(body(s, "rock_boulders").fill.points.size(), 100u);
}

TEST(Boulders, BadKeysAreRefusedWithKeyAndLine) {
  const auto refused = [](const std::string& from, const std::string& to, const std::string& key,
                          const std::string& at) {
    const std::string text = with(from, to, kScene);
    expect_names(error_of(text), line_of(text, at), key);
  };
  refused("volume_fraction = 0.2", "volume_fraction = 0.7", "body.rock.boulders.volume_fraction",
          "volume_fraction");
  refused("volume_fraction = 0.2", "volume_fraction = 0.0", "body.rock.boulders.volume_fraction",
          "volume_fraction");
  refused("radius_min = 0.025", "radius_min = 0.08", "body.rock.boulders.radius_min", "radius_min");
  refused("radius_min = 0.025", "radius_min = 0.01", "body.rock.boulders.radius_min",
          "radius_min");  // below the point spacing
  refused("exponent = 2.5", "exponnent = 2.5", "body.rock.boulders.exponnent", "exponnent");
  refused("radius_max = 0.075", "radius_max = 0.6", "body.rock.boulders.radius_max",
          "radius_max");  // larger than the host
  refused("material = \"basalt\"\nvolume_fraction", "material = \"cheese\"\nvolume_fraction",
          "body.rock.boulders.material", "cheese");
  // Equal spheres of 0.2 m cannot fill half of the cube.
  {
    const std::string text =
        with("radius_max = 0.075", "radius_max = 0.2",
             with("radius_min = 0.025", "radius_min = 0.2",
                  with("volume_fraction = 0.2", "volume_fraction = 0.5", kScene)));
    const std::string msg = error_of(text);
    expect_names(msg, line_of(text, "volume_fraction"), "body.rock.boulders.volume_fraction");
    EXPECT_NE(msg.find("cannot be reached"), std::string::npos) << msg;
  }
  // A region the host does not reach.
  {
    const std::string text = with(
        "exponent = 2.5", "exponent = 2.5\nregion_lo = [2, 2, 2]\nregion_hi = [3, 3, 3]", kScene);
    expect_names(error_of(text), line_of(text, "region_lo"), "body.rock.boulders.region_lo");
  }
  // No mirror symmetry.
  {
    const std::string text =
        with("end_time = 1.0e-6", "end_time = 1.0e-6\nsymmetry_plane = \"z\"",
             with("lo = [-0.6, -0.6, -0.6]", "lo = [-0.6, -0.6, 0.0]", kScene));
    expect_names(error_of(text), line_of(text, "[body.rock.boulders]"), "body.rock.boulders");
  }
}

TEST(Boulders, RegionKeepsTheFieldInsideIt) {
  const Scene s = parse(with("exponent = 2.5",
                             "exponent = 2.5\nregion_lo = [-0.5, -0.5, 0.0]\n"
                             "region_hi = [0.5, 0.5, 0.5]",
                             kScene));
  for (const Sphere& b : spheres(s)) EXPECT_GE(b.centre.z() - b.radius, 0.0);
  // The fraction is of the host inside the region: half the cube's volume.
  const BodySpec& f = body(s, "rock_boulders");
  EXPECT_NEAR(f.fill.volume / 0.5, 0.2, 0.01);
}

}  // namespace
}  // namespace shatter::scene
