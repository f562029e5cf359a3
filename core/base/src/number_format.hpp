#pragma once
/// Number formatting for messages (private to the core).
#include <charconv>
#include <cmath>
#include <cstdio>
#include <string>
#include <string_view>

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

/// User text for a message with its control bytes spelt out ("\\x00"): a NUL byte from a file
/// would otherwise end the message where it is printed, and a carriage return overwrite it.
inline std::string printable(std::string_view text) {
  std::string out;
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte == 0x7f) {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\x%02x", byte);
      out += escaped;
    } else {
      out += c;
    }
  }
  return out;
}

}  // namespace granular
