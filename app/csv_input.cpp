/// csv_input.hpp.
#include "csv_input.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "csv_output.hpp"

namespace granular::app {
namespace {

std::vector<std::string> splitCells(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  std::istringstream in(line);
  while (std::getline(in, cell, ',')) cells.push_back(cell);
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

bool parseNumber(const std::string& text, double& value) {
  if (text.empty()) {
    value = std::numeric_limits<double>::quiet_NaN();
    return true;
  }
  const auto r = std::from_chars(text.data(), text.data() + text.size(), value);
  return r.ec == std::errc() && r.ptr == text.data() + text.size();
}

}  // namespace

const std::vector<double>& CsvTable::column(const std::string& name) const {
  for (std::size_t c = 0; c < header.size(); ++c) {
    if (header[c] == name) return columns[c];
  }
  throw IoError(file.string() + ": no column '" + name + "'");
}

const std::vector<std::string>& CsvTable::text(const std::string& name) const {
  for (std::size_t c = 0; c < textHeader.size(); ++c) {
    if (textHeader[c] == name) return textColumns[c];
  }
  throw IoError(file.string() + ": no column '" + name + "'");
}

CsvTable readCsv(const std::filesystem::path& file, const std::vector<std::string>& textColumns) {
  std::ifstream in(file);
  if (!in) throw IoError(file.string() + ": cannot open");
  CsvTable table;
  table.file = file;
  std::string line;
  if (!std::getline(in, line)) throw IoError(file.string() + ": empty file, expected a header");
  const std::vector<std::string> names = splitCells(line);
  std::vector<bool> numeric(names.size(), true);
  std::vector<std::vector<double>> all(names.size());
  std::vector<std::vector<std::string>> texts(names.size());
  std::vector<bool> asText(names.size());
  for (std::size_t c = 0; c < names.size(); ++c) {
    asText[c] = std::find(textColumns.begin(), textColumns.end(), names[c]) != textColumns.end();
  }
  for (long lineNo = 2; std::getline(in, line); ++lineNo) {
    if (line.empty()) continue;
    const std::vector<std::string> cells = splitCells(line);
    if (cells.size() != names.size()) {
      throw IoError(file.string() + ":" + std::to_string(lineNo) + ": " +
                    std::to_string(cells.size()) + " cells, the header has " +
                    std::to_string(names.size()));
    }
    for (std::size_t c = 0; c < cells.size(); ++c) {
      double v = 0;
      if (asText[c]) texts[c].push_back(cells[c]);
      if (!parseNumber(cells[c], v)) numeric[c] = false;
      all[c].push_back(v);
    }
    table.lines.push_back(lineNo);
  }
  for (std::size_t c = 0; c < names.size(); ++c) {
    if (asText[c]) {
      table.textHeader.push_back(names[c]);
      table.textColumns.push_back(std::move(texts[c]));
    }
    if (!numeric[c]) continue;
    table.header.push_back(names[c]);
    table.columns.push_back(std::move(all[c]));
  }
  return table;
}

std::vector<std::string> nonFiniteCells(const CsvTable& table,
                                        const std::vector<std::string>& columns) {
  constexpr std::size_t kListed = 3;  // line numbers named; the rest are counted
  std::vector<std::string> found;
  for (const std::string& name : columns) {
    const std::vector<double>& values = table.column(name);
    std::string lines;
    std::size_t count = 0;
    bool nan = false, inf = false;
    for (std::size_t row = 0; row < values.size(); ++row) {
      if (std::isfinite(values[row])) continue;
      (std::isnan(values[row]) ? nan : inf) = true;
      if (count++ < kListed)
        lines += (lines.empty() ? "" : ", ") + std::to_string(table.lines[row]);
    }
    if (count == 0) continue;
    if (count > kListed) lines += " and " + std::to_string(count - kListed) + " more";
    found.push_back((count == 1 ? "line " : "lines ") + lines + ", column " + name + ": " +
                    (nan && inf ? "nan or inf"
                     : nan      ? "nan"
                                : "inf"));
  }
  return found;
}

std::map<std::string, std::string> readKeyValues(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw IoError(file.string() + ": cannot open");
  std::map<std::string, std::string> kv;
  for (std::string line; std::getline(in, line);) {
    const auto eq = line.find(" = ");
    if (eq != std::string::npos) kv[line.substr(0, eq)] = line.substr(eq + 3);
  }
  return kv;
}

double numberAt(const std::map<std::string, std::string>& values, const std::string& key,
                const std::filesystem::path& file) {
  const auto it = values.find(key);
  double v = 0;
  if (it == values.end() || !parseNumber(it->second, v) || std::isnan(v)) {
    throw IoError(file.string() + ": missing or non-numeric '" + key + "'");
  }
  return v;
}

}  // namespace granular::app
