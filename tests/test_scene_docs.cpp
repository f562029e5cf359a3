/// docs/scenes.md against the validator (issue 9): every key a scene table accepts is documented
/// in its section of the reference, and every key documented there is accepted, so the two
/// cannot drift apart. The keys come from core/scene/src/scene_schema.hpp, the lists the loader
/// checks tables against.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>

#include "scene_schema.hpp"

namespace {

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
        key.pop_back();
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
