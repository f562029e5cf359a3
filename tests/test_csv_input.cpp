/// Reading back the commands' CSV files (csv_input.hpp): which cells hold no number, by the
/// file's line and the column's name.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "csv_input.hpp"

namespace fs = std::filesystem;

// Line numbers are the file's (the header is line 1, a blank line still counts); an empty cell
// reads as nan; beyond three lines the rest are counted.
TEST(CsvInput, NonFiniteCellsNameTheirLinesAndColumn) {
  const fs::path file = fs::temp_directory_path() / "granular_csv_non_finite.csv";
  std::ofstream(file) << "time_s,a,b,c\n"
                         "0,1,nan,1\n"
                         "\n"
                         "0.1,inf,2,\n"
                         "0.2,3,nan,nan\n"
                         "0.3,4,nan,-inf\n"
                         "0.4,5,nan,nan\n"
                         "0.5,6,nan,7\n";
  const granular::app::CsvTable table = granular::app::readCsv(file);
  EXPECT_EQ(table.lines, (std::vector<long>{2, 4, 5, 6, 7, 8}));
  EXPECT_EQ(
      granular::app::nonFiniteCells(table, {"time_s", "a", "b", "c"}),
      (std::vector<std::string>{"line 4, column a: inf", "lines 2, 5, 6 and 2 more, column b: nan",
                                "lines 4, 5, 6 and 1 more, column c: nan or inf"}));
  EXPECT_TRUE(granular::app::nonFiniteCells(table, {"time_s"}).empty());
  fs::remove(file);
}
