/// docs/scenes.md against the validator (issue 9): every key a scene table accepts is documented
/// in its section of the reference, and every key documented there is accepted, so the two
/// cannot drift apart. The keys come from core/scene/src/scene_schema.hpp, the lists the loader
/// checks tables against.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include "granular/contact_model.hpp"
#include "scene_schema.hpp"

namespace {

/// One row of a key table: the key and its unit, range and default columns as written.
struct DocRow {
  std::string unit, range, defaultText;
};

std::string trimmed(const std::string& text) {
  const std::size_t begin = text.find_first_not_of(' ');
  if (begin == std::string::npos) return {};
  return text.substr(begin, text.find_last_not_of(' ') - begin + 1);
}

/// The rows of docs/scenes.md's [material] table, by key.
std::map<std::string, DocRow> materialRows() {
  std::ifstream in(std::filesystem::path(GRANULAR_SOURCE_DIR) / "docs/scenes.md");
  std::map<std::string, DocRow> rows;
  std::string line;
  bool inMaterial = false;
  while (std::getline(in, line)) {
    if (line.rfind("## ", 0) == 0) inMaterial = line.rfind("## `[material]`", 0) == 0;
    if (!inMaterial || line.rfind("| `", 0) != 0) continue;
    std::vector<std::string> cells;
    std::stringstream row(line.substr(1));
    std::string cell;
    while (std::getline(row, cell, '|')) cells.push_back(trimmed(cell));
    if (cells.size() < 4) continue;
    const std::string key = cells[0].substr(1, cells[0].size() - 2);  // without the backquotes
    rows[key] = {cells[1], cells[2], cells[3]};
  }
  return rows;
}

/// What disagrees between the declared parameters and the documented rows: a key on one side
/// only, a unit, a range (the declared interval must open the range column) or a default.
std::vector<std::string> materialDocProblems(std::span<const granular::ParameterSpec> table,
                                             const std::map<std::string, DocRow>& rows) {
  std::vector<std::string> problems;
  std::set<std::string> declared;
  for (const granular::ParameterSpec& p : table) {
    const std::string key(p.key);
    declared.insert(key);
    const auto row = rows.find(key);
    if (row == rows.end()) {
      problems.push_back("accepted but not documented: " + key);
      continue;
    }
    const DocRow& d = row->second;
    if (d.unit != p.unit)
      problems.push_back(key + ": unit '" + d.unit + "', declared " + std::string(p.unit));
    if (p.kind == granular::ParameterKind::Number) {
      if (d.range.rfind(p.range.bounds(), 0) != 0) {
        problems.push_back(key + ": range '" + d.range + "', declared " + p.range.bounds());
      }
      std::size_t used = 0;
      double value = std::nan("");
      try {
        value = std::stod(d.defaultText, &used);
      } catch (const std::exception&) {
      }
      if (value != p.defaultValue) {
        problems.push_back(key + ": default '" + d.defaultText + "', declared " +
                           p.valueText(p.defaultValue));
      }
    } else if (d.defaultText != p.valueText(p.defaultValue) &&
               d.defaultText != "`" + p.valueText(p.defaultValue) + "`") {
      problems.push_back(key + ": default '" + d.defaultText + "', declared " +
                         p.valueText(p.defaultValue));
    }
  }
  for (const auto& [key, row] : rows) {
    if (!declared.count(key)) problems.push_back("documented but not accepted: " + key);
  }
  return problems;
}

/// Section name (as scene_schema::Table::name) → keys in its tables' first column.
std::map<std::string, std::set<std::string>> documentedKeys() {
  std::ifstream in(std::filesystem::path(GRANULAR_SOURCE_DIR) / "docs/scenes.md");
  std::map<std::string, std::set<std::string>> keys;
  std::string section, line;
  bool prose = true;  // outside a key section (before the first, or the outputs)
  while (std::getline(in, line)) {
    auto starts = [&](const char* prefix) { return line.rfind(prefix, 0) == 0; };
    if (starts("## ")) prose = false;
    if (starts("## Top level")) {
      section.clear();
    } else if (starts("## `[[particles]]`")) {
      section = "particles";
      keys[""].insert(section);
    } else if (starts("### `type = \"grid\"`")) {
      section = "particles.grid";
      keys[section].insert("type");
    } else if (starts("### `type = \"csv\"`")) {
      section = "particles.csv";
      keys[section].insert("type");
    } else if (starts("### `[[")) {  // ### `[[stages.inserts]]`: an array inside a table
      section = line.substr(7, line.find(']', 7) - 7);
    } else if (starts("## `[")) {  // ## `[material]`, ## `[[stages]]`
      std::string bare;
      for (std::size_t k = 4; k < line.size() && line[k] != '`'; ++k) {
        if (line[k] != '[' && line[k] != ']') bare += line[k];
      }
      section = bare;
      keys[""].insert(bare);  // a table is a key of the top level
    } else if (starts("## ")) {
      prose = true;  // outputs, notes
    } else if (starts("| `") && !prose && section != "particles") {
      std::string key = line.substr(3, line.find('`', 3) - 3);
      if (key.front() == '[') {  // [stages.wall_velocity]: a sub-table
        key = key.substr(key.rfind('.') + 1);
        while (!key.empty() && key.back() == ']') key.pop_back();
      }
      keys[section].insert(key);
    }
  }
  return keys;
}

}  // namespace

TEST(SceneDocs, EveryAcceptedKeyIsDocumentedAndEveryDocumentedKeyIsAccepted) {
  const auto documented = documentedKeys();
  ASSERT_GE(documented.size(), 8u) << "docs/scenes.md lost its sections";
  for (const auto& table : granular::scene_schema::kTables) {
    const std::string name(table.name);
    SCOPED_TRACE("table '" + name + "'");
    ASSERT_TRUE(documented.count(name)) << "no section for it in docs/scenes.md";
    const std::set<std::string>& docs = documented.at(name);
    std::set<std::string> accepted;
    for (std::string_view k : table.keys) accepted.insert(std::string(k));
    for (const std::string& k : accepted) {
      EXPECT_TRUE(docs.count(k)) << "accepted but not documented: " << k;
    }
    for (const std::string& k : docs) {
      EXPECT_TRUE(accepted.count(k)) << "documented but not accepted: " << k;
    }
  }
}

TEST(SceneDocs, TheMaterialTableIsTheContactModelsDeclarations) {
  const auto rows = materialRows();
  ASSERT_GE(rows.size(), 5u) << "docs/scenes.md lost its [material] table";
  for (const std::string& problem : materialDocProblems(granular::materialParameters(), rows)) {
    ADD_FAILURE() << problem;
  }
}

TEST(SceneDocs, ATermAddedToTheTableMustBeDocumented) {
  std::vector<granular::ParameterSpec> table(granular::materialParameters().begin(),
                                             granular::materialParameters().end());
  granular::ParameterSpec dummy;
  dummy.key = "dummy_stiffness";
  dummy.unit = "N/m";
  table.push_back(dummy);
  const std::vector<std::string> problems = materialDocProblems(table, materialRows());
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems[0], "accepted but not documented: dummy_stiffness");
}
