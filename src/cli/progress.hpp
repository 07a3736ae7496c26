#pragma once
// Human-readable numbers for the progress line.

#include <string>

namespace shatter::cli {

// "12.3 us", "4.56 ms", "100 s"
std::string format_time(double seconds);
// "1h02m", "3m20s", "12s"
std::string format_duration(double seconds);

}  // namespace shatter::cli
