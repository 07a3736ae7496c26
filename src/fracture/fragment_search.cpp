// Fragment labelling: the MPM paper's grid-based density clustering (Sec. 4.1.2) and BA95's
// friends-of-friends with a damaged veneer (Sec. 4.4). All work happens in cell-sorted order
// built from the id-sorted (canonical) order, so labels do not depend on storage order.

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "damage/principal.hpp"
#include "fracture/cell_grid.hpp"
#include "fracture/rings.hpp"
#include "shatter/fracture/fragments.hpp"

namespace shatter {
namespace {

using fracture::CellGrid;

constexpr std::int64_t kNone = -1;

// Point data gathered in cell-sorted order, and the neighbour query on it.
struct Cloud {
  std::vector<double> x, y, z, vol;
  std::vector<double> h;  // per point linking length (BA95: smoothing length); empty = link2
  std::vector<std::uint8_t> failed;
  const CellGrid* grid = nullptr;
  double link2 = 0.0;

  // Calls f(j) for every point j != k closer than the linking length (with per-point lengths,
  // their mean h_jk, as the SPH kernel's h_ij).
  template <class F>
  void for_each_friend(std::uint32_t k, F&& f) const {
    grid->for_each_neighbour_cell(grid->cell_of(k), [&](std::uint32_t c) {
      const auto& cell = grid->cells()[c];
      for (std::uint32_t j = cell.begin; j < cell.end; ++j) {
        if (j == k) continue;
        const double dx = x[j] - x[k], dy = y[j] - y[k], dz = z[j] - z[k];
        const double r2 = dx * dx + dy * dy + dz * dz;
        if (h.empty()) {
          if (r2 <= link2) f(j);
        } else {
          const double l = 0.5 * (h[j] + h[k]);
          if (r2 <= l * l) f(j);
        }
      }
    });
  }
  double dist2(std::uint32_t a, std::uint32_t b) const {
    const double dx = x[a] - x[b], dy = y[a] - y[b], dz = z[a] - z[b];
    return dx * dx + dy * dy + dz * dz;
  }
};

// Friends-of-friends components of the points with seed[k] != 0, numbered in sorted order of
// their first point (so the numbering is canonical).
std::int64_t grow_components(const Cloud& cloud, const std::vector<std::uint8_t>& seed,
                             std::vector<std::int64_t>& label) {
  const auto n = static_cast<std::uint32_t>(label.size());
  std::int64_t next = 0;
  std::vector<std::uint32_t> stack;
  for (std::uint32_t k = 0; k < n; ++k) {
    if (!seed[k] || label[k] != kNone) continue;
    label[k] = next;
    stack.push_back(k);
    while (!stack.empty()) {
      const std::uint32_t a = stack.back();
      stack.pop_back();
      cloud.for_each_friend(a, [&](std::uint32_t j) {
        if (seed[j] && label[j] == kNone) {
          label[j] = next;
          stack.push_back(j);
        }
      });
    }
    ++next;
  }
  return next;
}

// Attaches unlabelled eligible points touching labelled ones, level by level (at most `levels`
// levels). Each new point joins the fragment of its nearest already-labelled friend (ties: the
// lower label); labels of one level are computed from the previous level only, so the result does
// not depend on the order in which points are visited.
void attach(const Cloud& cloud, const std::vector<std::uint8_t>& eligible,
            std::vector<std::int64_t>& label, int levels) {
  const auto n = static_cast<std::uint32_t>(label.size());
  // Nearest labelled friend of j (ties: lower label); kNone if j touches no labelled point.
  const auto nearest_label = [&](std::uint32_t j) {
    double best = std::numeric_limits<double>::infinity();
    std::int64_t chosen = kNone;
    cloud.for_each_friend(j, [&](std::uint32_t i) {
      if (label[i] == kNone) return;
      const double d2 = cloud.dist2(i, j);
      if (d2 < best || (d2 == best && label[i] < chosen)) {
        best = d2;
        chosen = label[i];
      }
    });
    return chosen;
  };
  // Level 1 scans the eligible points (usually far fewer than the labelled ones).
  std::vector<std::uint32_t> frontier;
  std::vector<std::int64_t> chosen;
  for (std::uint32_t j = 0; j < n; ++j) {
    if (!eligible[j] || label[j] != kNone) continue;
    const std::int64_t l = nearest_label(j);
    if (l != kNone) {
      frontier.push_back(j);
      chosen.push_back(l);
    }
  }
  for (std::size_t c = 0; c < frontier.size(); ++c) label[frontier[c]] = chosen[c];
  // Later levels grow from the points added by the previous one.
  std::vector<std::uint8_t> queued(n, 0);
  std::vector<std::uint32_t> candidates;
  for (int level = 1; level < levels && !frontier.empty(); ++level) {
    candidates.clear();
    for (std::uint32_t k : frontier)
      cloud.for_each_friend(k, [&](std::uint32_t j) {
        if (label[j] == kNone && eligible[j] && !queued[j]) {
          queued[j] = 1;
          candidates.push_back(j);
        }
      });
    chosen.resize(candidates.size());
    for (std::size_t c = 0; c < candidates.size(); ++c) chosen[c] = nearest_label(candidates[c]);
    for (std::size_t c = 0; c < candidates.size(); ++c) label[candidates[c]] = chosen[c];
    frontier.swap(candidates);
  }
}

// BA95 Sec. 4.4: friends within one SPH smoothing length, h = factor (m / rho)^{1/3}, per point
// in storage order; `h_max` is the largest.
std::vector<double> smoothing_lengths(const ParticleStore& store, double factor, double& h_max) {
  if (!store.has(Field::mass) || !store.has(Field::rho)) {
    throw std::logic_error(
        "fragment search: linking by smoothing length needs the mass and rho columns");
  }
  const std::size_t n = store.size();
  const auto m = store.col(Field::mass), rho = store.col(Field::rho);
  std::vector<double> smoothing(n);
  h_max = 0.0;
  for (std::size_t p = 0; p < n; ++p) {
    smoothing[p] = factor * std::cbrt(m[p] / rho[p]);
    if (!(smoothing[p] > 0.0) || !std::isfinite(smoothing[p])) {
      throw std::invalid_argument("fragment search: particle " + std::to_string(p) +
                                  " has no finite positive smoothing length (mass / rho)");
    }
    h_max = std::max(h_max, smoothing[p]);
  }
  return smoothing;
}

// Origin half a spacing below the lowest point: a lattice starting at the bounding-box corner
// then fills whole cells with 2x2x2 points when h = 2 x spacing (the paper's set-up).
void grid_origin(const ParticleStore& store, double spacing, double lo[3]) {
  const auto xs = store.col(Field::x), ys = store.col(Field::y), zs = store.col(Field::z);
  for (int a = 0; a < 3; ++a) lo[a] = std::numeric_limits<double>::infinity();
  for (std::size_t p = 0; p < store.size(); ++p) {
    lo[0] = std::min(lo[0], xs[p]);
    lo[1] = std::min(lo[1], ys[p]);
    lo[2] = std::min(lo[2], zs[p]);
  }
  for (int a = 0; a < 3; ++a) lo[a] -= 0.5 * spacing;
}

// Per point in storage order: failed by damage, or (BA95 Sec. 4.4, with static_strength > 0) by
// a largest principal tension above the static strength, at which it would still break at the
// low strain rates after the simulation ends.
std::vector<std::uint8_t> failed_points(const ParticleStore& store,
                                        const FragmentSearchSpec& spec) {
  const std::size_t n = store.size();
  const bool has_damage = store.has(Field::damage);
  const bool pre_pass = spec.method == "friends_of_friends" && spec.static_strength > 0.0;
  const auto damage = has_damage ? store.col(Field::damage) : std::span<const double>{};
  std::span<const double> stress[6];
  if (pre_pass) {
    const Field f[6] = {Field::sxx, Field::syy, Field::szz, Field::sxy, Field::syz, Field::sxz};
    for (int c = 0; c < 6; ++c) stress[c] = store.col(f[c]);
  }
  std::vector<std::uint8_t> failed(n, 0);
  for (std::size_t p = 0; p < n; ++p) {
    bool f = has_damage && damage[p] >= spec.damage_threshold;
    if (pre_pass && !f) {
      const double s[6] = {stress[0][p], stress[1][p], stress[2][p],
                           stress[3][p], stress[4][p], stress[5][p]};
      f = damage::largest_principal(s) >= spec.static_strength;
    }
    failed[p] = f ? 1 : 0;
  }
  return failed;
}

// The points gathered in the grid's cell-sorted order.
// `measure` is each point's volume0 (3-D) or its ring's cross-section (r-z), storage order.
Cloud gather_cloud(const ParticleStore& store, const CellGrid& grid, double link,
                   const std::vector<double>& smoothing, const std::vector<std::uint8_t>& failed,
                   std::span<const double> measure) {
  const std::size_t n = store.size();
  const auto xs = store.col(Field::x), ys = store.col(Field::y), zs = store.col(Field::z);
  const auto order = grid.order();
  Cloud cloud;
  cloud.grid = &grid;
  cloud.link2 = link * link;
  cloud.x.resize(n);
  cloud.y.resize(n);
  cloud.z.resize(n);
  cloud.vol.resize(n);
  if (!smoothing.empty()) cloud.h.resize(n);
  cloud.failed.assign(n, 0);
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint32_t p = order[k];
    cloud.x[k] = xs[p];
    cloud.y[k] = ys[p];
    cloud.z[k] = zs[p];
    cloud.vol[k] = measure[p];
    if (!smoothing.empty()) cloud.h[k] = smoothing[p];
    cloud.failed[k] = failed[p];
  }
  return cloud;
}

// The fragments of the cloud (labels in cell-sorted order): the MPM paper's grid-density
// clustering (Sec. 4.1.2) or friends-of-friends of the unfailed points, then the failed boundary
// layer one point thick (both methods). `h` is the grid's cell size.
std::vector<std::int64_t> cluster(const Cloud& cloud, const CellGrid& grid,
                                  const FragmentSearchSpec& spec, double h) {
  const std::size_t n = cloud.x.size();
  std::vector<std::uint8_t> unfailed(n), failed_flag(n);
  for (std::size_t k = 0; k < n; ++k) {
    unfailed[k] = cloud.failed[k] ? 0 : 1;
    failed_flag[k] = cloud.failed[k];
  }
  std::vector<std::int64_t> sorted_label(n, kNone);
  if (spec.method == "grid_density") {
    // Extendable points: unfailed points in cells whose unfailed material fills at least
    // extendable_ratio of the cell (the paper's per-cell ratio in place of DBSCAN's count). In
    // r-z the cells are squares of the half-plane and the points' measure their cross-sections.
    const double cell_volume = spec.axisymmetric ? h * h : h * h * h;
    std::vector<std::uint8_t> extendable(n, 0);
    for (const auto& cell : grid.cells()) {
      double filled = 0.0;
      for (std::uint32_t k = cell.begin; k < cell.end; ++k)
        if (unfailed[k]) filled += cloud.vol[k];
      const bool dense = filled >= spec.extendable_ratio * cell_volume;
      for (std::uint32_t k = cell.begin; k < cell.end; ++k) extendable[k] = dense && unfailed[k];
    }
    grow_components(cloud, extendable, sorted_label);
    // Non-extendable unfailed points never link two fragments: they join, level by level, the
    // fragment that reaches them first (a thin neck is split between its two sides).
    std::vector<std::uint8_t> border(n);
    for (std::size_t k = 0; k < n; ++k) border[k] = unfailed[k] && !extendable[k];
    attach(cloud, border, sorted_label, std::numeric_limits<int>::max());
  } else {
    grow_components(cloud, unfailed, sorted_label);
  }
  attach(cloud, failed_flag, sorted_label, 1);
  return sorted_label;
}

}  // namespace

std::vector<std::int64_t> label_fragments(const ParticleStore& store,
                                          const FragmentSearchSpec& spec) {
  if (spec.method != "grid_density" && spec.method != "friends_of_friends")
    throw std::invalid_argument("fragment search: unknown method '" + spec.method +
                                "' (known: grid_density, friends_of_friends)");
  const std::size_t n = store.size();
  std::vector<std::int64_t> labels(n, kNone);
  if (n == 0) return labels;
  if (!store.has(Field::volume0))
    throw std::logic_error("fragment search: the particle store has no volume0 column");

  // r-z: the half-plane search on the rings' cross-sections (their spacing is sqrt(mean A)).
  const std::vector<double> areas =
      spec.axisymmetric ? fracture::ring_areas(store) : std::vector<double>{};
  const std::span<const double> measure =
      spec.axisymmetric ? std::span<const double>(areas) : store.col(Field::volume0);
  const auto canonical = fracture::canonical_order(
      store.has(IField::id) ? store.col(IField::id) : std::span<const std::int64_t>{}, n);
  double total_measure = 0.0;
  for (std::uint32_t p : canonical) total_measure += measure[p];
  const double mean = total_measure / static_cast<double>(n);
  const double spacing = spec.axisymmetric ? std::sqrt(mean) : std::cbrt(mean);
  double h = spec.cell_size > 0.0 ? spec.cell_size : 2.0 * spacing;
  const double link = spec.linking_length > 0.0 ? spec.linking_length : 1.5 * spacing;
  if (!(h > 0.0)) throw std::invalid_argument("fragment search: particle volumes are zero");
  std::vector<double> smoothing;
  if (spec.method == "friends_of_friends" && spec.smoothing_factor > 0.0) {
    double h_max = 0.0;
    smoothing = smoothing_lengths(store, spec.smoothing_factor, h_max);
    h = std::max(h, h_max);  // friends are within max h: the 27 cells around a point hold them
  } else if (link > h) {
    throw std::invalid_argument("fragment search: linking_length exceeds cell_size");
  }

  double lo[3];
  grid_origin(store, spacing, lo);
  const CellGrid grid(store.col(Field::x), store.col(Field::y), store.col(Field::z), canonical, lo,
                      h);
  const Cloud cloud =
      gather_cloud(store, grid, link, smoothing, failed_points(store, spec), measure);
  const std::vector<std::int64_t> sorted_label = cluster(cloud, grid, spec, h);
  const auto order = grid.order();
  for (std::size_t k = 0; k < n; ++k) labels[order[k]] = sorted_label[k];
  return labels;
}

FragmentCatalogue find_fragments(ParticleStore& store, const FragmentSearchSpec& spec) {
  auto labels = label_fragments(store, spec);
  FragmentCatalogue cat = fragment_kinematics(store, labels, spec.axisymmetric);
  if (store.has(IField::fragment)) {
    auto out = store.col(IField::fragment);
    std::copy(labels.begin(), labels.end(), out.begin());
  }
  return cat;
}

}  // namespace shatter
