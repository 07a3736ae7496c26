#include "progress.hpp"

#include <cmath>

#include <fmt/format.h>

namespace shatter::cli {

std::string format_time(double s) {
  const double a = std::abs(s);
  if (a == 0.0) return "0 s";
  if (a < 1e-6) return fmt::format("{:.3g} ns", s * 1e9);
  if (a < 1e-3) return fmt::format("{:.3g} us", s * 1e6);
  if (a < 1.0) return fmt::format("{:.3g} ms", s * 1e3);
  return fmt::format("{:.4g} s", s);
}

std::string format_duration(double s) {
  if (!std::isfinite(s) || s < 0) return "?";
  // Beyond this (11 years) the estimate is meaningless and would overflow the integer below.
  if (s >= 3.6e8) return ">100000h";
  const auto t = static_cast<long long>(std::llround(s));
  if (t >= 3600) return fmt::format("{}h{:02d}m", t / 3600, (t % 3600) / 60);
  if (t >= 60) return fmt::format("{}m{:02d}s", t / 60, t % 60);
  return fmt::format("{}s", t);
}

}  // namespace shatter::cli
