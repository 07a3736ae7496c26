#include "shatter/scene/mesh.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>
#include <Eigen/Geometry>

namespace shatter::scene {
namespace {

using Vec3 = Eigen::Vector3d;

[[noreturn]] void fail(const std::filesystem::path& file, std::size_t line, const std::string& m) {
  throw std::invalid_argument(line > 0 ? fmt::format("{}:{}: {}", file.string(), line, m)
                                       : fmt::format("{}: {}", file.string(), m));
}

std::string read_all(const std::filesystem::path& file) {
  std::error_code ec;
  const auto status = std::filesystem::status(file, ec);
  if (!std::filesystem::exists(status)) fail(file, 0, "no such mesh file");
  if (!std::filesystem::is_regular_file(status)) fail(file, 0, "is not a regular file");
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file, 0, "cannot read the mesh file");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

bool parse_double(const std::string& s, double& v) {
  char* end = nullptr;
  v = std::strtod(s.c_str(), &end);
  return end != s.c_str() && *end == '\0' && std::isfinite(v);
}

std::vector<std::string> tokens_of(const std::string& line) {
  std::vector<std::string> t;
  std::istringstream in(line);
  for (std::string w; in >> w;) t.push_back(w);
  return t;
}

Vec3 read_xyz(const std::vector<std::string>& t, std::size_t first, const std::filesystem::path& f,
              std::size_t line, const char* what) {
  Vec3 v;
  if (t.size() < first + 3) fail(f, line, fmt::format("{} needs three numbers", what));
  for (std::size_t k = 0; k < 3; ++k) {
    if (!parse_double(t[first + k], v[static_cast<Eigen::Index>(k)])) {
      fail(f, line, fmt::format("{}: '{}' is not a finite number", what, t[first + k]));
    }
  }
  return v;
}

TriangleMesh read_obj(const std::filesystem::path& file, const std::string& text) {
  TriangleMesh m;
  struct Face {
    std::vector<long> refs;
    std::size_t line;
  };
  std::vector<Face> faces;
  std::istringstream in(text);
  std::string line;
  for (std::size_t n = 1; std::getline(in, line); ++n) {
    if (const auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    const auto t = tokens_of(line);
    if (t.empty()) continue;
    if (t[0] == "v") {
      m.vertices.push_back(read_xyz(t, 1, file, n, "a vertex (v)"));
    } else if (t[0] == "f") {
      if (t.size() < 4) fail(file, n, "a face (f) needs at least three vertices");
      Face f{{}, n};
      for (std::size_t k = 1; k < t.size(); ++k) {
        // "i", "i/t", "i//n" or "i/t/n": the vertex index is the first field.
        const std::string idx = t[k].substr(0, t[k].find('/'));
        char* end = nullptr;
        const long i = std::strtol(idx.c_str(), &end, 10);
        if (idx.empty() || *end != '\0' || i == 0) {
          fail(file, n, fmt::format("'{}' is not a vertex index (1-based, or negative)", t[k]));
        }
        // A negative index counts back from the last vertex read so far.
        f.refs.push_back(i > 0 ? i - 1 : static_cast<long>(m.vertices.size()) + i);
      }
      faces.push_back(std::move(f));
    }
    // vt, vn, o, g, s, usemtl, mtllib, l, p: not part of the surface.
  }
  for (const Face& f : faces) {
    for (long r : f.refs) {
      if (r < 0 || r >= static_cast<long>(m.vertices.size())) {
        fail(file, f.line,
             fmt::format("vertex index {} is out of range (the file has {} vertices)", r + 1,
                         m.vertices.size()));
      }
    }
    for (std::size_t k = 1; k + 1 < f.refs.size(); ++k) {
      m.triangles.push_back({static_cast<std::uint32_t>(f.refs[0]),
                             static_cast<std::uint32_t>(f.refs[k]),
                             static_cast<std::uint32_t>(f.refs[k + 1])});
    }
  }
  return m;
}

// STL stores each triangle's corners; corners with equal coordinates are one vertex.
class Welder {
 public:
  explicit Welder(TriangleMesh& m) : m_(m) {}
  std::uint32_t operator()(const Vec3& v) {
    const auto [it, added] =
        index_.try_emplace({v.x(), v.y(), v.z()}, static_cast<std::uint32_t>(m_.vertices.size()));
    if (added) m_.vertices.push_back(v);
    return it->second;
  }

 private:
  TriangleMesh& m_;
  std::map<std::array<double, 3>, std::uint32_t> index_;
};

TriangleMesh read_stl_ascii(const std::filesystem::path& file, const std::string& text) {
  TriangleMesh m;
  Welder weld(m);
  std::istringstream in(text);
  std::string line;
  std::vector<Vec3> loop;
  std::size_t loop_line = 0;
  bool in_loop = false;
  for (std::size_t n = 1; std::getline(in, line); ++n) {
    const auto t = tokens_of(line);
    if (t.empty()) continue;
    const std::string& k = t[0];
    if (k == "vertex") {
      if (!in_loop) fail(file, n, "'vertex' outside an 'outer loop'");
      loop.push_back(read_xyz(t, 1, file, n, "a vertex"));
    } else if (k == "outer") {
      if (in_loop) fail(file, n, "'outer loop' inside another loop");
      in_loop = true;
      loop_line = n;
      loop.clear();
    } else if (k == "endloop") {
      if (!in_loop) fail(file, n, "'endloop' without 'outer loop'");
      if (loop.size() != 3) {
        fail(file, loop_line,
             fmt::format("a facet's loop has {} vertices (STL facets are triangles)", loop.size()));
      }
      m.triangles.push_back({weld(loop[0]), weld(loop[1]), weld(loop[2])});
      in_loop = false;
    } else if (k != "solid" && k != "facet" && k != "endfacet" && k != "endsolid") {
      fail(file, n, fmt::format("unexpected '{}' in an ASCII STL file", k));
    }
  }
  if (in_loop) fail(file, loop_line, "'outer loop' without 'endloop'");
  return m;
}

TriangleMesh read_stl_binary(const std::filesystem::path& file, const std::string& data) {
  static_assert(std::endian::native == std::endian::little, "binary STL is little-endian");
  std::uint32_t count = 0;
  std::memcpy(&count, data.data() + 80, 4);
  TriangleMesh m;
  Welder weld(m);
  for (std::uint32_t t = 0; t < count; ++t) {
    const char* rec = data.data() + 84 + std::size_t{50} * t;
    std::array<std::uint32_t, 3> tri{};
    for (int c = 0; c < 3; ++c) {
      float xyz[3];
      std::memcpy(xyz, rec + 12 + 12 * c, 12);  // after the normal's 12 bytes
      const Vec3 v(xyz[0], xyz[1], xyz[2]);
      if (!v.allFinite()) {
        fail(file, 0, fmt::format("triangle {} has a vertex that is not finite", t + 1));
      }
      tri[static_cast<std::size_t>(c)] = weld(v);
    }
    m.triangles.push_back(tri);
  }
  return m;
}

TriangleMesh read_stl(const std::filesystem::path& file, const std::string& data) {
  // Binary when the size matches the declared triangle count (some binary headers start with
  // "solid" too), else ASCII when it starts with "solid".
  if (data.size() >= 84) {
    std::uint32_t count = 0;
    std::memcpy(&count, data.data() + 80, 4);
    if (data.size() == 84 + std::size_t{50} * count) return read_stl_binary(file, data);
  }
  const auto first = data.find_first_not_of(" \t\r\n");
  if (first != std::string::npos && data.compare(first, 5, "solid") == 0) {
    return read_stl_ascii(file, data);
  }
  if (data.size() < 84) fail(file, 0, "neither ASCII STL (no 'solid') nor binary STL (< 84 bytes)");
  std::uint32_t count = 0;
  std::memcpy(&count, data.data() + 80, 4);
  fail(file, 0,
       fmt::format("binary STL declares {} triangles ({} bytes) but the file has {} bytes, and it "
                   "is not ASCII STL (no 'solid')",
                   count, 84 + std::size_t{50} * count, data.size()));
}

std::string point(const Vec3& v) {
  return fmt::format("[{:g}, {:g}, {:g}]", v.x(), v.y(), v.z());
}

double cross2(double dx, double dy, double qx, double qy) {
  return dx * qy - dy * qx;
}

}  // namespace

TriangleMesh read_mesh(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext != ".obj" && ext != ".stl") {
    fail(file, 0, fmt::format("unknown mesh format '{}' (.obj or .stl)", ext));
  }
  const std::string data = read_all(file);
  TriangleMesh m = ext == ".obj" ? read_obj(file, data) : read_stl(file, data);
  // Triangles with a repeated corner enclose nothing and have no edges of their own.
  std::erase_if(m.triangles,
                [](const auto& t) { return t[0] == t[1] || t[1] == t[2] || t[0] == t[2]; });
  if (m.triangles.empty()) fail(file, 0, "holds no triangles");
  return m;
}

void check_closed(const TriangleMesh& m) {
  // Per undirected edge (lo, hi): how often it is used as lo->hi and as hi->lo.
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::array<int, 2>> edges;
  for (const auto& t : m.triangles) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = t[static_cast<std::size_t>(k)],
                          b = t[static_cast<std::size_t>((k + 1) % 3)];
      auto& e = edges[{std::min(a, b), std::max(a, b)}];
      ++e[a < b ? 0 : 1];
    }
  }
  std::size_t open = 0, shared = 0, same_way = 0;
  std::string open_example, shared_example, same_example;
  for (const auto& [key, use] : edges) {
    const std::string where = fmt::format("the edge from {} to {}", point(m.vertices[key.first]),
                                          point(m.vertices[key.second]));
    const int n = use[0] + use[1];
    if (n == 1) {
      if (open++ == 0) open_example = where;
    } else if (n > 2) {
      if (shared++ == 0) shared_example = where;
    } else if (use[0] != 1) {
      if (same_way++ == 0) same_example = where;
    }
  }
  if (open > 0) {
    throw std::invalid_argument(fmt::format(
        "the mesh is not closed: {} edges belong to one triangle only, e.g. {} (a body needs a "
        "watertight surface; fill the holes in a mesh editor)",
        open, open_example));
  }
  if (shared > 0) {
    throw std::invalid_argument(
        fmt::format("the mesh is not a simple closed surface: {} edges are shared by more than two "
                    "triangles, e.g. {}",
                    shared, shared_example));
  }
  if (same_way > 0) {
    throw std::invalid_argument(fmt::format(
        "the mesh's triangles are not consistently oriented: {} edges are used twice in the "
        "same direction, e.g. {} (some triangles are flipped)",
        same_way, same_example));
  }
}

MeshSolid::MeshSolid(TriangleMesh mesh) : mesh_(std::move(mesh)) {
  lo_ = hi_ = mesh_.vertices.front();
  for (const Vec3& v : mesh_.vertices) {
    lo_ = lo_.cwiseMin(v);
    hi_ = hi_.cwiseMax(v);
  }
  for (const auto& t : mesh_.triangles) {
    volume_ += mesh_.vertices[t[0]].dot(mesh_.vertices[t[1]].cross(mesh_.vertices[t[2]])) / 6.0;
  }
  orientation_ = volume_ < 0.0 ? -1.0 : 1.0;
  volume_ = std::abs(volume_);
  // About two triangles per bin on a sphere-like surface (one layer above, one below).
  const int n =
      std::clamp(static_cast<int>(std::ceil(std::sqrt(mesh_.triangles.size() / 2.0))), 1, 1024);
  nx_ = ny_ = n;
  bin_x_ = std::max((hi_.x() - lo_.x()) / n, 1e-300);
  bin_y_ = std::max((hi_.y() - lo_.y()) / n, 1e-300);
  bins_.resize(static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_));
  auto bin_of = [](double v, double lo, double w, int count) {
    return std::clamp(static_cast<int>(std::floor((v - lo) / w)), 0, count - 1);
  };
  for (std::uint32_t k = 0; k < mesh_.triangles.size(); ++k) {
    const auto& t = mesh_.triangles[k];
    Vec3 a = mesh_.vertices[t[0]], b = a;
    for (int c = 1; c < 3; ++c) {
      a = a.cwiseMin(mesh_.vertices[t[static_cast<std::size_t>(c)]]);
      b = b.cwiseMax(mesh_.vertices[t[static_cast<std::size_t>(c)]]);
    }
    for (int j = bin_of(a.y(), lo_.y(), bin_y_, ny_); j <= bin_of(b.y(), lo_.y(), bin_y_, ny_);
         ++j) {
      for (int i = bin_of(a.x(), lo_.x(), bin_x_, nx_); i <= bin_of(b.x(), lo_.x(), bin_x_, nx_);
           ++i) {
        bins_[static_cast<std::size_t>(j) * static_cast<std::size_t>(nx_) +
              static_cast<std::size_t>(i)]
            .push_back(k);
      }
    }
  }
}

bool MeshSolid::contains(const Vec3& p) const {
  return winding(p) != 0;
}

std::optional<Vec3> MeshSolid::find_overlap(int n) const {
  const Vec3 step = (hi_ - lo_) / n;
  for (int k = 0; k < n; ++k) {
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        const Vec3 p = lo_ + step.cwiseProduct(Vec3(i + 0.5, j + 0.5, k + 0.5));
        if (std::abs(winding(p)) > 1) return p;
      }
    }
  }
  return std::nullopt;
}

int MeshSolid::winding(const Vec3& p) const {
  if ((p.array() < lo_.array()).any() || (p.array() > hi_.array()).any()) return 0;
  const int i = std::clamp(static_cast<int>(std::floor((p.x() - lo_.x()) / bin_x_)), 0, nx_ - 1);
  const int j = std::clamp(static_cast<int>(std::floor((p.y() - lo_.y()) / bin_y_)), 0, ny_ - 1);
  int crossings = 0;
  for (const std::uint32_t k : bins_[static_cast<std::size_t>(j) * static_cast<std::size_t>(nx_) +
                                     static_cast<std::size_t>(i)]) {
    std::array<std::uint32_t, 3> t = mesh_.triangles[k];
    const Vec3* v[3] = {&mesh_.vertices[t[0]], &mesh_.vertices[t[1]], &mesh_.vertices[t[2]]};
    const double area = cross2(v[1]->x() - v[0]->x(), v[1]->y() - v[0]->y(), v[2]->x() - v[0]->x(),
                               v[2]->y() - v[0]->y());
    if (area == 0.0) continue;  // seen edge-on from the ray: its neighbours' edges decide
    // Facing +z (counter-clockwise seen from above): the ray leaves the solid through it.
    const int sign = area > 0.0 ? 1 : -1;
    if (area < 0.0) {  // counter-clockwise in x-y from here on
      std::swap(v[1], v[2]);
      std::swap(t[1], t[2]);
    }
    double e[3];  // e[c]: edge from corner c to corner c+1; > 0 inside
    bool inside = true;
    for (int c = 0; c < 3 && inside; ++c) {
      const int d = (c + 1) % 3;
      const Vec3& u = *v[c];
      const Vec3& w = *v[d];
      // Evaluated along the edge's canonical direction (lower vertex index first), so the two
      // triangles sharing the edge compute the same number, negated.
      const bool forward = t[static_cast<std::size_t>(c)] < t[static_cast<std::size_t>(d)];
      const Vec3& s = forward ? u : w;
      const Vec3& f = forward ? w : u;
      const double canon = cross2(f.x() - s.x(), f.y() - s.y(), p.x() - s.x(), p.y() - s.y());
      e[c] = forward ? canon : -canon;
      if (e[c] > 0.0) continue;
      if (e[c] < 0.0) {
        inside = false;
        continue;
      }
      // On the edge: it belongs to the triangle for which it is a "left" or "top" edge, which
      // is exactly one of the two (their directions are opposite).
      const double dx = w.x() - u.x(), dy = w.y() - u.y();
      inside = dy > 0.0 || (dy == 0.0 && dx < 0.0);
    }
    if (!inside) continue;
    // Height of the triangle's plane above p (barycentric weights e[] / sum).
    const double sum = e[0] + e[1] + e[2];
    const double z = sum != 0.0 ? (e[1] * v[0]->z() + e[2] * v[1]->z() + e[0] * v[2]->z()) / sum
                                : std::max({v[0]->z(), v[1]->z(), v[2]->z()});
    if (z > p.z()) crossings += sign;
  }
  return crossings;
}

}  // namespace shatter::scene
