#pragma once
/// Reading back what the commands wrote: numeric CSV tables and "key = value" files, with errors
/// that name the file, the line and the column.
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace granular::app {

/// A CSV file of numbers with a header line; empty cells read as NaN.
class CsvTable {
 public:
  std::filesystem::path file;
  std::vector<std::string> header;
  std::vector<std::vector<double>> columns;  ///< columns[c][row]
  std::vector<long> lines;                   ///< the file's line number of each row (header: 1)
  /// The columns asked for as text (readCsv's `textColumns`), each cell as written.
  std::vector<std::string> textHeader;
  std::vector<std::vector<std::string>> textColumns;  ///< textColumns[c][row]

  /// The column of that header name; IoError naming the file and the name if absent.
  const std::vector<double>& column(const std::string& name) const;
  /// The text column of that name; IoError naming the file and the name if it was not read.
  const std::vector<std::string>& text(const std::string& name) const;
  std::size_t rows() const { return columns.empty() ? 0 : columns[0].size(); }
};

/// Reads a numeric CSV table; non-numeric columns (a stage name) are skipped, but those named in
/// `textColumns` are kept as text whatever they hold (a wall's name may be a number).
CsvTable readCsv(const std::filesystem::path& file,
                 const std::vector<std::string>& textColumns = {});

/// The cells of `columns` (names in `table`'s header) that hold no finite number, one message a
/// column: "line 5, column R33_top_N: nan" or "lines 5, 9, 12 and 2 more, column R33_top_N: nan
/// or inf" (an empty cell reads as nan). Empty when every cell is finite.
std::vector<std::string> nonFiniteCells(const CsvTable& table,
                                        const std::vector<std::string>& columns);

/// Reads "key = value" lines.
std::map<std::string, std::string> readKeyValues(const std::filesystem::path& file);

/// The number under `key`; IoError naming the file and key if absent or not a number.
double numberAt(const std::map<std::string, std::string>& values, const std::string& key,
                const std::filesystem::path& file);

}  // namespace granular::app
