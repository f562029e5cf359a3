#pragma once
/// Number formatting for messages (private to the core).
#include <charconv>
#include <cmath>
#include <string>

namespace granular {

/// Shortest decimal that reads back to the same double ("0.3", "1e+12", "nan", "-inf"), so that
/// a message repeats the value the user wrote rather than "0.29999999999999999".
inline std::string formatNumber(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, x);
  return std::string(buffer, result.ptr);
}

}  // namespace granular
