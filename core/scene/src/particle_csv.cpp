/// Particle CSV reader (see particle_csv.hpp). Sections: 1. fields and numbers; 2. the header;
/// 3. the rows.
#include "particle_csv.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>
#include <optional>
#include <string>
#include <string_view>

#include "fnv1a.hpp"
#include "granular/error.hpp"
#include "granular/output_file.hpp"
#include "nearest_name.hpp"
#include "number_format.hpp"

namespace granular {

namespace {

// 1. Fields and numbers ---------------------------------------------------------------------------

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

// 2. The header -----------------------------------------------------------------------------------

/// The quantities a row can give, in the order of `Columns::of`.
enum Quantity { X, Y, Z, R, VX, VY, VZ, WX, WY, WZ, M, kQuantities };
constexpr std::array<std::string_view, kQuantities> kNames = {"x",  "y",  "z",  "r",  "vx",  "vy",
                                                              "vz", "wx", "wy", "wz", "mass"};
/// Columns granular writes in its state files that a saved state's reader passes over: the
/// rows' order numbers the particles, and a snapshot's step and time are the file's, not the
/// new run's.
constexpr std::array<std::string_view, 3> kStateOnly = {"id", "step", "time_s"};
/// Ends every header message, so that a user sees what a header may hold.
constexpr std::string_view kKnownParticleColumns =
    "the columns are x, y, z and r (or radius), optionally vx, vy, vz and wx, wy, wz, in any "
    "order, each once";
constexpr std::string_view kKnownStateColumns =
    "a saved state's columns are x, y, z, radius (or r) and mass, optionally vx, vy, vz and wx, "
    "wy, wz, in any order, each once, as granular writes them in final_state.csv and its "
    "snapshots (id, step and time_s are passed over)";

/// Which column gives each quantity (-1: none), from the header's names.
struct Columns {
  std::array<int, kQuantities> of;
  std::vector<std::string> names;  ///< the header's names, as written (for row messages)
  bool has(Quantity q) const { return of[q] >= 0; }
};

/// What to tell a user whose column name is not one of ours: the likely intent where we can
/// guess it, the nearest name where it is one slip away.
std::string hintFor(std::string_view name) {
  if (name == "diameter" || name == "d" || name == "dia" || name == "diam") {
    return "; did you mean r, the radius (half the diameter)?";
  }
  if (name == "id" || name == "mass" || name == "step" || name == "time_s") {
    return "; granular writes it in its particle files but a particle file does not read it "
           "(the rows' order numbers the particles and the mass follows from the density): "
           "drop the column, or give the file as a saved state (type = \"state\") to start "
           "from it as it is";
  }
  std::vector<std::string_view> candidates(kNames.begin(), kNames.end());
  candidates.push_back("radius");
  std::string_view best;
  std::size_t bestDistance = name.size() + 1;
  for (std::string_view candidate : candidates) {
    const std::size_t d = editDistance(name, candidate);
    if (d < bestDistance) bestDistance = d, best = candidate;
  }
  // One slip only: the names are one or two letters, so two slips reach almost any of them.
  return bestDistance <= 1 ? "; did you mean '" + std::string(best) + "'?" : std::string();
}

Columns readHeader(std::string_view text, const std::string& where, CsvKind kind) {
  const bool state = kind == CsvKind::SavedState;
  const std::string_view known = state ? kKnownStateColumns : kKnownParticleColumns;
  const std::vector<std::string_view> fields = splitFields(text);
  if (fields.size() == 1 && text.find(';') != std::string_view::npos) {
    throw ConfigError(where + "the header '" + printable(text) +
                      "' has no commas: separate the columns with commas; " + std::string(known));
  }
  Columns columns;
  columns.of.fill(-1);
  for (std::size_t c = 0; c < fields.size(); ++c) {
    const std::string_view name = fields[c];
    const std::string number = "column " + std::to_string(c + 1);
    if (name.empty()) {
      throw ConfigError(where + number + " of the header has no name (a stray comma?); " +
                        std::string(known));
    }
    if (state && std::find(kStateOnly.begin(), kStateOnly.end(), name) != kStateOnly.end()) {
      columns.names.emplace_back(name);  // passed over
      continue;
    }
    int quantity = -1;
    for (int q = 0; q < kQuantities; ++q) {
      if (name == kNames[std::size_t(q)]) quantity = q;
    }
    if (name == "radius") quantity = R;
    if (quantity == M && !state) quantity = -1;  // a particle file's mass follows the density
    if (quantity < 0) {
      throw ConfigError(where + number + " '" + printable(name) + "' is not a particle column" +
                        hintFor(name) + "; " + std::string(known));
    }
    if (const int earlier = columns.of[std::size_t(quantity)]; earlier >= 0) {
      throw ConfigError(where + "columns " + std::to_string(earlier + 1) + " (" +
                        columns.names[std::size_t(earlier)] + ") and " + std::to_string(c + 1) +
                        " (" + std::string(name) + ") both give " +
                        (quantity == R ? std::string("the radius") : std::string(name)) + "; " +
                        std::string(known));
    }
    columns.of[std::size_t(quantity)] = int(c);
    columns.names.emplace_back(name);
  }
  std::string missing;
  for (Quantity q : {X, Y, Z, R, M}) {
    if (columns.has(q) || (q == M && !state)) continue;
    missing += missing.empty() ? "" : ", ";
    missing += kNames[q];
  }
  if (!missing.empty()) {
    throw ConfigError(where + "the header has no column " + missing + "; " + std::string(known));
  }
  for (Quantity first : {VX, WX}) {
    const int given =
        columns.has(first) + columns.has(Quantity(first + 1)) + columns.has(Quantity(first + 2));
    if (given == 0 || given == 3) continue;
    std::string absent;
    for (int q = first; q < first + 3; ++q) {
      if (columns.has(Quantity(q))) continue;
      absent += absent.empty() ? "" : ", ";
      absent += kNames[std::size_t(q)];
    }
    throw ConfigError(
        where + "the header has no column " + absent + ": " +
        (first == VX ? "a velocity (vx, vy, vz)" : "an angular velocity (wx, wy, wz)") +
        " needs all three columns or none");
  }
  return columns;
}

// 3. The rows -------------------------------------------------------------------------------------

CsvParticle readRow(std::string_view text, const Columns& columns, std::size_t row,
                    const std::string& where) {
  const std::vector<std::string_view> fields = splitFields(text);
  if (fields.size() != columns.names.size()) {
    std::string header;
    for (const std::string& name : columns.names) header += (header.empty() ? "" : ",") + name;
    throw ConfigError(where + "row " + std::to_string(row) + ": expected " +
                      std::to_string(columns.names.size()) + " fields, one per column of the " +
                      "header (" + header + "), got " + std::to_string(fields.size()));
  }
  std::array<double, kQuantities> values{};
  for (int q = 0; q < kQuantities; ++q) {
    const int c = columns.of[std::size_t(q)];
    if (c < 0) continue;
    const std::string_view field = fields[std::size_t(c)];
    const std::string column = "row " + std::to_string(row) + ", column " + std::to_string(c + 1) +
                               " (" + columns.names[std::size_t(c)] + ") = '" + printable(field) +
                               "': ";
    const std::optional<double> value = parseNumber(field);
    if (!value) throw ConfigError(where + column + "not a number");
    if (!std::isfinite(*value)) throw ConfigError(where + column + "must be a finite number");
    if (q == R && *value <= 0.0) throw ConfigError(where + column + "radius must be > 0");
    if (q == M && *value <= 0.0) throw ConfigError(where + column + "mass must be > 0");
    values[std::size_t(q)] = *value;
  }
  CsvParticle p;
  p.position = Vec3(values[X], values[Y], values[Z]);
  p.radius = values[R];
  p.velocity = Vec3(values[VX], values[VY], values[VZ]);
  p.angularVelocity = Vec3(values[WX], values[WY], values[WZ]);
  p.mass = values[M];
  return p;
}

/// The hash of the rows' values (ParticleCsv::contentHash).
std::uint64_t valuesHash(const std::vector<CsvParticle>& rows) {
  std::uint64_t h = kFnv1aOffset;
  for (const CsvParticle& p : rows) {
    const double values[] = {
        p.position.x(),        p.position.y(),       p.position.z(), p.radius,
        p.velocity.x(),        p.velocity.y(),       p.velocity.z(), p.angularVelocity.x(),
        p.angularVelocity.y(), p.angularVelocity.z()};
    h = fnv1a(reinterpret_cast<const char*>(values), sizeof values, h);
  }
  return h;
}

}  // namespace

ParticleCsv readParticleCsv(const std::filesystem::path& path, CsvKind kind) {
  // The whole file at once: its bytes are hashed (the run's fingerprint) and parsed from the
  // same copy, so the two always describe the same file. A folder or a device (/dev/zero) is
  // refused before reading, and a file larger than the memory left is never read: the scene
  // that names it is at fault, so the error is the scene's (exit status 2).
  std::string bytes;
  try {
    InputFile in(path, "particle file");
    const std::uint64_t available = availableMemoryBytes();
    bytes = in.readAll(available > 0 ? available / 2 : in.size());
  } catch (const IoError& e) {
    throw ConfigError(e.what());
  }

  ParticleCsv file;
  std::string_view rest = bytes;
  // A UTF-8 byte-order mark (spreadsheets save one) is not part of the first column's name.
  if (rest.starts_with("\xEF\xBB\xBF")) rest.remove_prefix(3);
  std::optional<Columns> columns;
  std::size_t lineNumber = 0;
  while (!rest.empty()) {
    const std::size_t newline = rest.find('\n');
    const std::string_view line = rest.substr(0, newline);
    rest.remove_prefix(newline == std::string_view::npos ? rest.size() : newline + 1);
    ++lineNumber;
    const std::string_view text = trim(line);
    if (text.empty() || text.front() == '#') continue;
    const std::string where = path.string() + ":" + std::to_string(lineNumber) + ": ";
    if (!columns) {
      // A numeric first line means the header was forgotten: reading it as a header would
      // silently drop a particle.
      if (isNumericLine(text)) {
        throw ConfigError(
            where + "expected a header line naming the columns, got numbers; " +
            std::string(kind == CsvKind::SavedState ? kKnownStateColumns : kKnownParticleColumns));
      }
      columns = readHeader(text, where, kind);
      continue;
    }
    file.rows.push_back(readRow(text, *columns, file.rows.size() + 1, where));
    file.rows.back().line = lineNumber;
  }
  if (file.rows.empty()) throw ConfigError(path.string() + ": no particle rows");
  file.contentHash = valuesHash(file.rows);
  return file;
}

}  // namespace granular
