#pragma once
/// Validated reading of one TOML table of a scene file (private to the core).
///
/// A TomlTableReader wraps a table at a dotted path ("material", "particles[0]") and hands out
/// typed values, each checked for type, finiteness and range. Every failure throws SceneError
/// with the message "file:line:column: key = value: what is wrong", so that an editor can jump
/// to the offending line. Unknown keys are caught up front (expectOnly) with a "did you mean"
/// suggestion, because a misspelt optional key would otherwise be silently ignored.
#include <array>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

#include "granular/value_range.hpp"
#include "granular/vec3.hpp"
#include "nearest_name.hpp"
#include "number_format.hpp"

namespace granular {

/// The allowed interval of a number (granular/value_range.hpp).
using Range = ValueRange;

/// A TOML value as the user would write it: 0.3, "hooke", [0, 0, -9.81], true.
std::string describeValue(const toml::node& node);
/// "file:line:column: " or "file: " when the region has no position.
std::string locationPrefix(const std::string& file, const toml::source_region& where);

class TomlTableReader {
 public:
  /// `path` is the dotted name of the table ("" for the root), `file` the name used in messages.
  TomlTableReader(const toml::table& table, std::string path, std::string file);
  /// Same, and checks at once that the table holds only `allowed` keys.
  TomlTableReader(const toml::table& table, std::string path, std::string file,
                  std::initializer_list<std::string_view> allowed);

  /// Throws on the first key not in `allowed`, suggesting the nearest allowed key.
  void expectOnly(const std::vector<std::string_view>& allowed) const;

  bool has(std::string_view key) const { return table_.contains(key); }
  const toml::table& table() const { return table_; }
  /// "material.friction", or "friction" at the root.
  std::string keyPath(std::string_view key) const;

  // Numbers accept TOML integers and floats; NaN and infinities are always refused.
  double number(std::string_view key, const Range& range) const;  ///< required
  double number(std::string_view key, double fallback, const Range& range) const;
  std::optional<double> optionalNumber(std::string_view key, const Range& range) const;
  /// Integers must be TOML integers (3, not 3.0) within [lo, hi].
  std::int64_t integer(std::string_view key, std::int64_t lo, std::int64_t hi) const;  ///< required
  std::int64_t integer(std::string_view key, std::int64_t fallback, std::int64_t lo,
                       std::int64_t hi) const;
  bool boolean(std::string_view key, bool fallback) const;
  std::string string(std::string_view key) const;  ///< required
  std::string string(std::string_view key, std::string fallback) const;
  /// A string from a fixed set; a near miss gets a suggestion. Required if `fallback` is empty.
  std::string choice(std::string_view key, std::string_view fallback,
                     const std::vector<std::string_view>& options) const;
  /// An array of exactly three numbers, each in `range`.
  Vec3 vec3(std::string_view key, const Range& range) const;  ///< required
  Vec3 vec3(std::string_view key, const Vec3& fallback, const Range& range) const;
  /// An array of exactly three integers, each in [lo, hi].
  std::array<std::int64_t, 3> integers3(std::string_view key, std::int64_t lo,
                                        std::int64_t hi) const;  ///< required
  /// An array of numbers, each in `range`; empty when the key is absent.
  std::vector<double> numbers(std::string_view key, const Range& range) const;
  /// An array of strings; `fallback` when the key is absent.
  std::vector<std::string> strings(std::string_view key, std::vector<std::string> fallback) const;
  /// A sub-table, or nullptr when absent.
  const toml::table* subTable(std::string_view key) const;
  /// An array of tables ([[key]]), or nullptr when absent.
  const toml::array* tableArray(std::string_view key) const;

  /// "file:line:col: path.key = value: ", what fail(key, ...) puts before its message: for a
  /// refusal that comes after the file is read.
  std::string messagePrefix(std::string_view key) const;
  /// Throws "file:line:col: path.key = value: message" at the key's position.
  [[noreturn]] void fail(std::string_view key, const std::string& message) const;
  /// Throws "file:line:col: path.key: required key is missing" at the table's position.
  [[noreturn]] void failMissing(std::string_view key) const;

 private:
  const toml::node& required(std::string_view key) const;
  [[noreturn]] void failType(std::string_view key, const toml::node& node,
                             std::string_view expected) const;
  double checkedNumber(const std::string& name, const toml::node& node, const Range& range,
                       const toml::source_region& where) const;
  std::int64_t checkedInteger(const std::string& name, const toml::node& node, std::int64_t lo,
                              std::int64_t hi, const toml::source_region& where) const;
  const toml::source_region& keyRegion(std::string_view key) const;
  [[noreturn]] void failAt(const toml::source_region& where, const std::string& message) const;

  const toml::table& table_;
  std::string path_;
  std::string file_;
};

}  // namespace granular
