/// Particle CSV reader (see particle_csv.hpp).
#include "particle_csv.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <optional>
#include <string>
#include <string_view>

#include "granular/error.hpp"

namespace granular {

namespace {

constexpr std::array<const char*, 7> kColumns = {"x", "y", "z", "r", "vx", "vy", "vz"};

std::string_view trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  const auto last = s.find_last_not_of(" \t\r");
  return s.substr(first, last - first + 1);
}

std::vector<std::string_view> splitFields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    fields.push_back(trim(line.substr(start, comma - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return fields;
}

/// The whole field as a double, or nothing. from_chars is locale-independent, unlike strtod.
std::optional<double> parseNumber(std::string_view field) {
  if (!field.empty() && field.front() == '+') field.remove_prefix(1);
  double value = 0.0;
  const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), value);
  if (field.empty() || error != std::errc() || end != field.data() + field.size()) {
    return std::nullopt;
  }
  return value;
}

bool isNumericLine(std::string_view line) {
  for (std::string_view field : splitFields(line)) {
    if (!parseNumber(field)) return false;
  }
  return true;
}

}  // namespace

std::vector<CsvParticle> readParticleCsv(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw ConfigError(path.string() + ": cannot open particle file");

  std::vector<CsvParticle> particles;
  std::string line;
  std::size_t lineNumber = 0;
  bool headerSeen = false;
  while (std::getline(in, line)) {
    ++lineNumber;
    const std::string_view text = trim(line);
    if (text.empty() || text.front() == '#') continue;
    const std::string where = path.string() + ":" + std::to_string(lineNumber) + ": ";
    if (!headerSeen) {
      // A numeric first line means the header was forgotten: reading it as a header would
      // silently drop a particle.
      if (isNumericLine(text)) {
        throw ConfigError(where + "expected a header line (x,y,z,r[,vx,vy,vz]), got numbers");
      }
      headerSeen = true;
      continue;
    }
    const std::size_t row = particles.size() + 1;
    const std::vector<std::string_view> fields = splitFields(text);
    if (fields.size() != 4 && fields.size() != 7) {
      throw ConfigError(where + "row " + std::to_string(row) +
                        ": expected 4 fields (x,y,z,r) or 7 " + "(x,y,z,r,vx,vy,vz), got " +
                        std::to_string(fields.size()));
    }
    std::array<double, 7> values{};
    for (std::size_t c = 0; c < fields.size(); ++c) {
      const std::string column = "row " + std::to_string(row) + ", column " +
                                 std::to_string(c + 1) + " (" + kColumns[c] + ") = '" +
                                 std::string(fields[c]) + "': ";
      const std::optional<double> value = parseNumber(fields[c]);
      if (!value) throw ConfigError(where + column + "not a number");
      if (!std::isfinite(*value)) throw ConfigError(where + column + "must be a finite number");
      if (c == 3 && *value <= 0.0) throw ConfigError(where + column + "radius must be > 0");
      values[c] = *value;
    }
    particles.push_back({Vec3(values[0], values[1], values[2]), values[3],
                         Vec3(values[4], values[5], values[6]), lineNumber});
  }
  if (in.bad()) throw ConfigError(path.string() + ": read error");
  if (particles.empty()) throw ConfigError(path.string() + ": no particle rows");
  return particles;
}

}  // namespace granular
