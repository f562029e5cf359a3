/// readMaterial: [material] read key by key from the contact model's table of parameters, then
/// checked against the model's rules (material_reader.hpp).
#include "material_reader.hpp"

#include <algorithm>
#include <string>
#include <vector>

namespace granular {

Material readMaterial(const TomlTableReader& root, const std::string& file,
                      std::span<const ParameterSpec> table) {
  Material m;
  const toml::table* section = root.subTable("material");
  if (!section) return m;
  const TomlTableReader r(*section, "material", file);
  std::vector<std::string_view> keys;
  for (const ParameterSpec& p : table) keys.push_back(p.key);
  r.expectOnly(keys);
  for (const ParameterSpec& p : table) {
    switch (p.kind) {
      case ParameterKind::Number:
        p.set(m, r.number(p.key, p.get(m), p.range));
        break;
      case ParameterKind::Choice: {
        const std::size_t now = static_cast<std::size_t>(p.get(m));
        const std::string name = r.choice(
            p.key, p.names[now], std::vector<std::string_view>(p.names.begin(), p.names.end()));
        p.set(m, double(std::find(p.names.begin(), p.names.end(), name) - p.names.begin()));
        break;
      }
      case ParameterKind::Flag:
        p.set(m, r.boolean(p.key, p.get(m) != 0.0) ? 1.0 : 0.0);
        break;
    }
  }
  const RuleProblem rule = materialRuleProblem(m);  // here, so that the message has a line
  if (!rule.key.empty()) r.fail(rule.key, std::string(rule.requirement));
  // A key the other values leave without effect is refused, as [simulation] refuses
  // step_safety beside a fixed step: the user believes it acts.
  for (const IdleParameter& idle : idleParameters(m)) {
    if (r.has(idle.key)) r.fail(idle.key, std::string(idle.reason));
  }
  return m;
}

}  // namespace granular
