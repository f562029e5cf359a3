/// Validated reading of one TOML table (see toml_table_reader.hpp).
/// Sections: 1. number formatting and value description; 2. edit distance; 3. the reader.
#include "toml_table_reader.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

#include "granular/error.hpp"

namespace granular {

// 1. Number formatting and value description ----------------------------------------------------

namespace {

std::string quoted(std::string_view s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + '"';
}

std::string typeName(const toml::node& node) {
  switch (node.type()) {
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a float";
    case toml::node_type::boolean:
      return "a boolean";
    case toml::node_type::array:
      return "an array of " + std::to_string(node.as_array()->size()) +
             (node.as_array()->size() == 1 ? " value" : " values");
    case toml::node_type::table:
      return "a table";
    default:
      return "a date/time";
  }
}

}  // namespace

std::string describeValue(const toml::node& node) {
  if (auto* s = node.as_string()) return quoted(s->get());
  if (auto* i = node.as_integer()) return std::to_string(i->get());
  if (auto* f = node.as_floating_point()) return formatNumber(f->get());
  if (auto* b = node.as_boolean()) return b->get() ? "true" : "false";
  if (auto* a = node.as_array()) {
    // Long arrays are cut: the message must stay one readable line.
    constexpr std::size_t kShown = 6;
    std::string out = "[";
    for (std::size_t i = 0; i < a->size() && i < kShown; ++i) {
      if (i > 0) out += ", ";
      out += describeValue(*a->get(i));
    }
    if (a->size() > kShown) out += ", ...";
    return out + "]";
  }
  if (node.is_table()) return "{...}";
  return std::string(typeName(node));
}

std::string locationPrefix(const std::string& file, const toml::source_region& where) {
  std::ostringstream out;
  out << file;
  if (where.begin.line > 0) out << ':' << where.begin.line << ':' << where.begin.column;
  out << ": ";
  return out.str();
}

// 2. Edit distance
// ---------------------------------------------------------------------------------

namespace {

std::string joined(const std::vector<std::string_view>& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (i > 0) out += ", ";
    // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on "'" + std::string + "'".
    out += '\'';
    out += names[i];
    out += '\'';
  }
  return out;
}

}  // namespace

// 3. The reader
// -------------------------------------------------------------------------------------

TomlTableReader::TomlTableReader(const toml::table& table, std::string path, std::string file)
    : table_(table), path_(std::move(path)), file_(std::move(file)) {}

TomlTableReader::TomlTableReader(const toml::table& table, std::string path, std::string file,
                                 std::initializer_list<std::string_view> allowed)
    : TomlTableReader(table, std::move(path), std::move(file)) {
  expectOnly(std::vector<std::string_view>(allowed));
}

void TomlTableReader::expectOnly(const std::vector<std::string_view>& allowed) const {
  for (auto&& [key, node] : table_) {
    if (std::find(allowed.begin(), allowed.end(), key.str()) != allowed.end()) continue;
    const std::string suggestion = nearestName(key.str(), allowed);
    const std::string hint = suggestion.empty() ? "valid keys are " + joined(allowed)
                                                : "did you mean '" + suggestion + "'?";
    failAt(key.source(), keyPath(key.str()) + ": unknown key; " + hint);
  }
}

std::string TomlTableReader::keyPath(std::string_view key) const {
  return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
}

void TomlTableReader::failAt(const toml::source_region& where, const std::string& message) const {
  throw SceneError(locationPrefix(file_, where) + message);
}

const toml::source_region& TomlTableReader::keyRegion(std::string_view key) const {
  const auto it = table_.find(key);
  return it != table_.end() ? it->first.source() : table_.source();
}

std::string TomlTableReader::messagePrefix(std::string_view key) const {
  const toml::node* node = table_.get(key);
  const std::string value = node ? " = " + describeValue(*node) : std::string();
  return locationPrefix(file_, keyRegion(key)) + keyPath(key) + value + ": ";
}

void TomlTableReader::fail(std::string_view key, const std::string& message) const {
  throw SceneError(messagePrefix(key) + message);
}

void TomlTableReader::failMissing(std::string_view key) const {
  // The root table has no useful position; a sub-table points at its header line.
  const toml::source_region where = path_.empty() ? toml::source_region{} : table_.source();
  failAt(where, keyPath(key) + ": required key is missing");
}

void TomlTableReader::failType(std::string_view key, const toml::node& node,
                               std::string_view expected) const {
  fail(key, "expected " + std::string(expected) + ", got " + std::string(typeName(node)));
}

const toml::node& TomlTableReader::required(std::string_view key) const {
  const toml::node* node = table_.get(key);
  if (!node) failMissing(key);
  return *node;
}

double TomlTableReader::checkedNumber(const std::string& name, const toml::node& node,
                                      const Range& range, const toml::source_region& where) const {
  if (!node.is_number()) {
    failAt(where, name + " = " + describeValue(node) + ": expected a number, got " +
                      std::string(typeName(node)));
  }
  // toml++ gives no double for an integer a double cannot hold exactly (above 2^53): take the
  // nearest one, which is what the number means at a double's precision.
  const double x = node.is_integer() ? static_cast<double>(node.as_integer()->get())
                                     : node.as_floating_point()->get();
  if (!std::isfinite(x)) {
    // "must be > 0" becomes "must be finite and > 0".
    const std::string bound = range.describe().substr(std::string_view("must be ").size());
    failAt(where, name + " = " + describeValue(node) + ": must be finite" +
                      (bound == "a finite number" ? "" : " and " + bound));
  }
  if (!range.contains(x))
    failAt(where, name + " = " + describeValue(node) + ": " + range.describe());
  return x;
}

std::int64_t TomlTableReader::checkedInteger(const std::string& name, const toml::node& node,
                                             std::int64_t lo, std::int64_t hi,
                                             const toml::source_region& where) const {
  const auto* value = node.as_integer();
  if (!value) {
    failAt(where, name + " = " + describeValue(node) + ": expected an integer, got " +
                      std::string(typeName(node)));
  }
  const std::int64_t i = value->get();
  if (i < lo || i > hi) {
    const std::string bound =
        hi == std::numeric_limits<std::int64_t>::max()
            ? "must be >= " + std::to_string(lo)
            : "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
    failAt(where, name + " = " + describeValue(node) + ": " + bound);
  }
  return i;
}

double TomlTableReader::number(std::string_view key, const Range& range) const {
  return checkedNumber(keyPath(key), required(key), range, keyRegion(key));
}

double TomlTableReader::number(std::string_view key, double fallback, const Range& range) const {
  return has(key) ? number(key, range) : fallback;
}

std::optional<double> TomlTableReader::optionalNumber(std::string_view key,
                                                      const Range& range) const {
  if (!has(key)) return std::nullopt;
  return number(key, range);
}

std::int64_t TomlTableReader::integer(std::string_view key, std::int64_t lo,
                                      std::int64_t hi) const {
  return checkedInteger(keyPath(key), required(key), lo, hi, keyRegion(key));
}

std::int64_t TomlTableReader::integer(std::string_view key, std::int64_t fallback, std::int64_t lo,
                                      std::int64_t hi) const {
  return has(key) ? integer(key, lo, hi) : fallback;
}

bool TomlTableReader::boolean(std::string_view key, bool fallback) const {
  const toml::node* node = table_.get(key);
  if (!node) return fallback;
  if (!node->is_boolean()) failType(key, *node, "true or false");
  return node->as_boolean()->get();
}

std::string TomlTableReader::string(std::string_view key) const {
  const toml::node& node = required(key);
  if (!node.is_string()) failType(key, node, "a string");
  return node.as_string()->get();
}

std::string TomlTableReader::string(std::string_view key, std::string fallback) const {
  return has(key) ? string(key) : std::move(fallback);
}

std::string TomlTableReader::choice(std::string_view key, std::string_view fallback,
                                    const std::vector<std::string_view>& options) const {
  if (!has(key) && !fallback.empty()) return std::string(fallback);
  const std::string value = string(key);
  if (std::find(options.begin(), options.end(), value) != options.end()) return value;
  const std::string suggestion = nearestName(value, options);
  fail(key, "must be one of " + joined(options) +
                (suggestion.empty() ? "" : "; did you mean '" + suggestion + "'?"));
}

Vec3 TomlTableReader::vec3(std::string_view key, const Range& range) const {
  const toml::node& node = required(key);
  const toml::array* array = node.as_array();
  if (!array || array->size() != 3) failType(key, node, "an array of 3 numbers");
  Vec3 v;
  for (int i = 0; i < 3; ++i) {
    const toml::node& element = *array->get(std::size_t(i));
    v[i] = checkedNumber(keyPath(key) + "[" + std::to_string(i) + "]", element, range,
                         element.source());
  }
  return v;
}

Vec3 TomlTableReader::vec3(std::string_view key, const Vec3& fallback, const Range& range) const {
  return has(key) ? vec3(key, range) : fallback;
}

std::array<std::int64_t, 3> TomlTableReader::integers3(std::string_view key, std::int64_t lo,
                                                       std::int64_t hi) const {
  const toml::node& node = required(key);
  const toml::array* array = node.as_array();
  if (!array || array->size() != 3) failType(key, node, "an array of 3 integers");
  std::array<std::int64_t, 3> out{};
  for (std::size_t i = 0; i < 3; ++i) {
    const toml::node& element = *array->get(i);
    out[i] = checkedInteger(keyPath(key) + "[" + std::to_string(i) + "]", element, lo, hi,
                            element.source());
  }
  return out;
}

std::vector<double> TomlTableReader::numbers(std::string_view key, const Range& range) const {
  const toml::node* node = table_.get(key);
  if (!node) return {};
  const toml::array* array = node->as_array();
  if (!array) failType(key, *node, "an array of numbers");
  std::vector<double> out;
  for (std::size_t i = 0; i < array->size(); ++i) {
    const toml::node& element = *array->get(i);
    out.push_back(checkedNumber(keyPath(key) + "[" + std::to_string(i) + "]", element, range,
                                element.source()));
  }
  return out;
}

std::vector<std::string> TomlTableReader::strings(std::string_view key,
                                                  std::vector<std::string> fallback) const {
  const toml::node* node = table_.get(key);
  if (!node) return fallback;
  const toml::array* array = node->as_array();
  if (!array) failType(key, *node, "an array of strings");
  std::vector<std::string> out;
  for (std::size_t i = 0; i < array->size(); ++i) {
    const toml::node& element = *array->get(i);
    if (!element.is_string()) {
      failAt(element.source(), keyPath(key) + "[" + std::to_string(i) +
                                   "] = " + describeValue(element) + ": expected a string, got " +
                                   std::string(typeName(element)));
    }
    out.push_back(element.as_string()->get());
  }
  return out;
}

const toml::table* TomlTableReader::subTable(std::string_view key) const {
  const toml::node* node = table_.get(key);
  if (!node) return nullptr;
  if (!node->is_table()) failType(key, *node, "a table");
  return node->as_table();
}

const toml::array* TomlTableReader::tableArray(std::string_view key) const {
  const toml::node* node = table_.get(key);
  if (!node) return nullptr;
  if (!node->is_array_of_tables())
    failType(key, *node, "an array of tables ([[" + std::string(key) + "]])");
  return node->as_array();
}

}  // namespace granular
