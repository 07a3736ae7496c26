#pragma once
// Counter-based random numbers (SplitMix64 finaliser, Steele et al. 2014): the value for
// (seed, key, stream) is a pure function of those three integers, so flaws drawn per particle id
// do not depend on thread count, particle order or how many numbers other particles drew.

#include <cstdint>

namespace shatter {

constexpr std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

// Three rounds so that neighbouring keys and streams give unrelated outputs.
constexpr std::uint64_t counter_hash(std::uint64_t seed, std::uint64_t key, std::uint64_t stream) {
  return splitmix64(splitmix64(splitmix64(seed) ^ key) ^ (stream * 0xD1B54A32D192ED03ULL));
}

// Uniform in the open interval (0, 1): 53 random bits, offset by half a step so that neither 0
// nor 1 occurs (log(u) stays finite).
constexpr double uniform_open01(std::uint64_t bits) {
  return (static_cast<double>(bits >> 11) + 0.5) * 0x1.0p-53;
}

constexpr double counter_uniform(std::uint64_t seed, std::uint64_t key, std::uint64_t stream) {
  return uniform_open01(counter_hash(seed, key, stream));
}

}  // namespace shatter
