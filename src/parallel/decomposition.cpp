#include "shatter/parallel/decomposition.hpp"

#include <algorithm>
#include <cstring>
#include <numeric>
#include <stdexcept>

#include <fmt/format.h>

#include "shatter/core/reorder.hpp"

namespace shatter::parallel {
namespace {

std::uint64_t spread(std::uint64_t v) {
  // 21 bits -> every third bit of 63.
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffULL;
  v = (v | v << 16) & 0x1f0000ff0000ffULL;
  v = (v | v << 8) & 0x100f00f00f00f00fULL;
  v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
  v = (v | v << 2) & 0x1249249249249249ULL;
  return v;
}

std::vector<Field> registered_fields(const ParticleStore& P) {
  std::vector<Field> out;
  for (std::size_t i = 0; i < kFieldCount; ++i) {
    if (P.has(static_cast<Field>(i))) out.push_back(static_cast<Field>(i));
  }
  return out;
}
std::vector<IField> registered_ifields(const ParticleStore& P) {
  std::vector<IField> out;
  for (std::size_t i = 0; i < kIFieldCount; ++i) {
    if (P.has(static_cast<IField>(i))) out.push_back(static_cast<IField>(i));
  }
  return out;
}

std::vector<std::int64_t> group_of(const ParticleStore& P) {
  std::vector<std::int64_t> g(P.size());
  for (std::size_t k = 0; k < P.groups().size(); ++k) {
    const Range r = P.groups()[k].range;
    std::fill(g.begin() + static_cast<std::ptrdiff_t>(r.begin),
              g.begin() + static_cast<std::ptrdiff_t>(r.end), static_cast<std::int64_t>(k));
  }
  return g;
}

}  // namespace

std::uint64_t morton(std::uint64_t k) {
  return spread(k >> 42) << 2 | spread(k >> 21) << 1 | spread(k);
}

namespace {
constexpr std::int64_t kOff = std::int64_t{1} << 20;
constexpr std::uint64_t kMask = (std::uint64_t{1} << 21) - 1;
std::int64_t coord(std::uint64_t k, int axis) {
  return static_cast<std::int64_t>((k >> (42 - 21 * axis)) & kMask) - kOff;
}
std::int64_t floor_div4(std::int64_t v) {
  return v >= 0 ? v / 4 : -((-v + 3) / 4);
}
bool reaches(std::int64_t b, std::int64_t plane) {
  return 4 * b + 3 >= plane - 3 && 4 * b <= plane + 3;
}
}  // namespace

std::uint64_t Decomposition::placed(std::uint64_t k) const {
  if (planes_.empty()) return k;
  std::int64_t c[3] = {coord(k, 0), coord(k, 1), coord(k, 2)};
  for (const auto& [axis, index] : planes_) {
    if (reaches(c[axis], index)) c[axis] = floor_div4(index);
  }
  return (static_cast<std::uint64_t>(c[0] + kOff) << 42) |
         (static_cast<std::uint64_t>(c[1] + kOff) << 21) | static_cast<std::uint64_t>(c[2] + kOff);
}

bool Decomposition::near_plane(std::uint64_t k) const {
  for (const auto& [axis, index] : planes_) {
    if (reaches(coord(k, axis), index)) return true;
  }
  return false;
}

void Decomposition::build(std::vector<std::pair<std::uint64_t, std::int64_t>> weights, int ranks) {
  for (auto& w : weights) w.first = morton(placed(w.first));
  std::sort(weights.begin(), weights.end());
  std::int64_t total = 0;
  for (const auto& w : weights) total += w.second;
  cuts_.assign(static_cast<std::size_t>(ranks), ~std::uint64_t{0});
  cuts_[0] = 0;
  std::int64_t before = 0;
  std::size_t i = 0;
  for (int r = 1; r < ranks; ++r) {
    // rank r starts at the first block with at least r/ranks of the particles before it
    const std::int64_t target = (total / ranks) * r + ((total % ranks) * r + ranks - 1) / ranks;
    while (i < weights.size() && before < target) before += weights[i++].second;
    if (i < weights.size()) cuts_[static_cast<std::size_t>(r)] = weights[i].first;
  }
  // Never decreasing (an empty rank shares its start with the next one).
  for (std::size_t r = 1; r < cuts_.size(); ++r) cuts_[r] = std::max(cuts_[r], cuts_[r - 1]);
}

int Decomposition::rank_of(std::uint64_t block_key) const {
  const std::uint64_t m = morton(placed(block_key));
  const auto it = std::upper_bound(cuts_.begin(), cuts_.end(), m);
  return static_cast<int>(it - cuts_.begin()) - 1;
}

Bytes pack_particles(const ParticleStore& P, std::span<const std::uint32_t> which) {
  const auto fields = registered_fields(P);
  const auto ifields = registered_ifields(P);
  const auto group = group_of(P);
  Bytes out;
  out.reserve(which.size() * (1 + fields.size() + ifields.size()) * 8);
  for (const std::uint32_t p : which) {
    put(out, group[p]);
    for (const Field f : fields) put(out, P.col(f)[p]);
    for (const IField f : ifields) put(out, P.col(f)[p]);
  }
  return out;
}

ParticleStore merge_particles(const ParticleStore& like, std::span<const std::uint8_t> keep,
                              const std::vector<Bytes>& received) {
  const auto fields = registered_fields(like);
  const auto ifields = registered_ifields(like);
  const std::size_t row = (1 + fields.size() + ifields.size()) * 8;
  const std::size_t G = like.groups().size();
  // Rows per group: kept particles first, then arrivals in rank order.
  std::vector<std::size_t> count(G, 0);
  const auto group = group_of(like);
  for (std::size_t p = 0; p < like.size(); ++p) {
    if (keep[p]) ++count[static_cast<std::size_t>(group[p])];
  }
  for (const Bytes& b : received) {
    if (b.size() % row != 0) {
      throw std::runtime_error(fmt::format(
          "parallel: a particle message of {} bytes is not a whole number of {}-byte rows "
          "(ranks disagree on the registered columns)",
          b.size(), row));
    }
    for (std::size_t at = 0; at < b.size(); at += row) {
      std::int64_t g = 0;
      std::memcpy(&g, b.data() + at, 8);
      if (g < 0 || static_cast<std::size_t>(g) >= G) {
        throw std::runtime_error(fmt::format("parallel: particle of unknown group {}", g));
      }
      ++count[static_cast<std::size_t>(g)];
    }
  }
  ParticleStore out;
  for (const Field f : fields) out.require(f);
  for (const IField f : ifields) out.require(f);
  std::vector<std::size_t> next(G);
  for (std::size_t g = 0; g < G; ++g) {
    next[g] = out.add_group(like.groups()[g].material, count[g]).begin;
  }
  for (std::size_t p = 0; p < like.size(); ++p) {
    if (!keep[p]) continue;
    const std::size_t q = next[static_cast<std::size_t>(group[p])]++;
    for (const Field f : fields) out.col(f)[q] = like.col(f)[p];
    for (const IField f : ifields) out.col(f)[q] = like.col(f)[p];
  }
  for (const Bytes& b : received) {
    Reader r(b);
    while (!r.done()) {
      const auto g = static_cast<std::size_t>(r.get<std::int64_t>());
      const std::size_t q = next[g]++;
      for (const Field f : fields) out.col(f)[q] = r.get<double>();
      for (const IField f : ifields) out.col(f)[q] = r.get<std::int64_t>();
    }
  }
  return out;
}

// Ids are unique, so the stable re-order is the one a plain sort by id gives.
void sort_by_id(ParticleStore& P) {
  if (!P.has(IField::id)) return;
  const auto id = P.col(IField::id);
  std::vector<std::uint32_t> order;
  reorder_groups_by(P, order, [&](std::uint32_t p) { return id[p]; });
}

ParticleStore gather_particles(const ParticleStore& local, const Comm& comm) {
  std::vector<std::uint32_t> all(local.size());
  std::iota(all.begin(), all.end(), 0U);
  std::vector<Bytes> received = comm.gather(pack_particles(local, all));
  std::vector<std::uint8_t> none(local.size(), 0);
  if (comm.rank() != 0) received.clear();
  ParticleStore out = merge_particles(local, none, received);
  sort_by_id(out);
  return out;
}

}  // namespace shatter::parallel
