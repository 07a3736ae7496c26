#pragma once
// A small hand-made particle store with two material groups, real and integer columns, and
// values that are not round numbers (so a lossy round trip would show).

#include <cmath>
#include <numbers>

#include "shatter/core/particles.hpp"

namespace shatter::test {

inline ParticleStore sample_store(std::size_t n0 = 5, std::size_t n1 = 3) {
  ParticleStore s;
  s.require(FieldSet{Field::x, Field::y, Field::z, Field::vx, Field::vy, Field::vz, Field::mass,
                     Field::volume0, Field::rho, Field::damage, Field::energy});
  s.require(IField::id);
  s.require(IField::body);
  s.add_group(0, n0);
  s.add_group(3, n1);
  for (std::size_t p = 0; p < s.size(); ++p) {
    const double q = static_cast<double>(p);
    s.col(Field::x)[p] = std::sqrt(2.0) * q;
    s.col(Field::y)[p] = -std::exp(-q);
    s.col(Field::z)[p] = 1e-3 / (q + 3.0);
    s.col(Field::vx)[p] = std::sin(q);
    s.col(Field::vy)[p] = std::cos(q) * 1e3;
    s.col(Field::vz)[p] = 0.1 * q;
    s.col(Field::mass)[p] = 1e-6 * (1.0 + q / 7.0);
    s.col(Field::volume0)[p] = 5.12e-10;
    s.col(Field::rho)[p] = 2700.0 + q / 3.0;
    s.col(Field::damage)[p] = q / static_cast<double>(s.size());
    s.col(Field::energy)[p] = std::numbers::pi * q;
    s.col(IField::id)[p] = static_cast<std::int64_t>(1000 + 7 * p);
    s.col(IField::body)[p] = p < n0 ? 0 : 1;
  }
  return s;
}

}  // namespace shatter::test
