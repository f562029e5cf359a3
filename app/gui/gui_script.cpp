#include "gui_script.hpp"

#include <sstream>
#include <stdexcept>

#include "granular/contact_model.hpp"

namespace granular::gui {

namespace {

/// What a verb takes after it; the syntax text and the parser both read this one table.
enum class Argument { None, Number, Value };

struct Verb {
  const char* name;
  Argument argument;
  const char* placeholder;  ///< as the syntax text shows the argument
};

constexpr Verb kVerbs[] = {
    {"run", Argument::None, ""},
    {"pause", Argument::None, ""},
    {"reset", Argument::None, ""},
    {"stage2", Argument::None, ""},
    {"step", Argument::Number, "N"},
    {"speed", Argument::Number, "N"},
    {"mu", Argument::Number, "X"},
    {"gamma-n", Argument::Number, "X"},
    {"gamma-t", Argument::Number, "X"},
    {"youngs-modulus", Argument::Number, "X"},
    {"material", Argument::Value, "KEY=X"},
    {"wall-velocity", Argument::Number, "X"},
    {"colour", Argument::Value, "force|speed|stress|none"},
    {"frames", Argument::Number, "N"},
    {"wait-steps", Argument::Number, "N"},
    {"screenshot", Argument::Value, "FILE"},
    {"save-view", Argument::Value, "FILE"},
    {"load-checkpoint", Argument::Value, "FILE"},
    {"save-checkpoint", Argument::Value, "FILE"},
    {"export-figures", Argument::Value, "DIR"},
    {"quit", Argument::None, ""},
};

const Verb* findVerb(const std::string& name) {
  for (const Verb& v : kVerbs) {
    if (name == v.name) return &v;
  }
  return nullptr;
}

}  // namespace

MaterialSetting materialSetting(const std::string& argument) {
  const std::size_t equals = argument.find('=');
  const std::string key = argument.substr(0, equals);
  const ParameterSpec* spec = findParameter(key);
  std::string keys;
  for (const ParameterSpec& p : materialParameters()) {
    if (p.kind != ParameterKind::Number) continue;
    keys += (keys.empty() ? "" : ", ") + std::string(p.key);
  }
  if (equals == std::string::npos || !spec || spec->kind != ParameterKind::Number) {
    throw std::invalid_argument("script: material '" + argument +
                                "': expected KEY=X with KEY one of " + keys);
  }
  const std::string text = argument.substr(equals + 1);
  std::size_t used = 0;
  double value = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (text.empty() || used != text.size()) {
    throw std::invalid_argument("script: material " + key + " needs a number, got '" + text + "'");
  }
  if (!spec->accepts(value)) {
    throw std::invalid_argument("script: material " + key + " = " + text + ": " +
                                spec->requirement());
  }
  return {spec, value};
}

std::vector<std::string> scriptVerbs() {
  std::vector<std::string> names;
  for (const Verb& v : kVerbs) names.emplace_back(v.name);
  return names;
}

std::string scriptSyntax() {
  std::string text;
  for (const Verb& v : kVerbs) {
    if (!text.empty()) text += ", ";
    text += v.name;
    if (v.argument != Argument::None) text += std::string(" ") + v.placeholder;
  }
  return text;
}

std::vector<ScriptCommand> parseScript(const std::string& text) {
  std::vector<ScriptCommand> commands;
  std::stringstream all(text);
  std::string item;
  while (std::getline(all, item, ';')) {
    std::stringstream parts(item);
    ScriptCommand c;
    if (!(parts >> c.verb)) continue;  // empty between two ';'
    parts >> c.argument;
    std::string extra;
    if (parts >> extra) {
      throw std::invalid_argument("script: '" + item + "': one argument at most");
    }
    const Verb* verb = findVerb(c.verb);
    if (!verb) {
      throw std::invalid_argument("script: unknown command '" + c.verb + "' (" + scriptSyntax() +
                                  ")");
    }
    switch (verb->argument) {
      case Argument::None:
        if (!c.argument.empty()) {
          throw std::invalid_argument("script: '" + c.verb + "' takes no argument");
        }
        break;
      case Argument::Number: {
        std::size_t used = 0;
        try {
          std::stod(c.argument, &used);
        } catch (const std::exception&) {
          used = 0;
        }
        if (c.argument.empty() || used != c.argument.size()) {
          throw std::invalid_argument("script: '" + c.verb + "' needs a number, got '" +
                                      c.argument + "'");
        }
        break;
      }
      case Argument::Value:
        if (c.argument.empty()) {
          throw std::invalid_argument("script: '" + c.verb + "' needs a value");
        }
        if (c.verb == "material") materialSetting(c.argument);  // throws if it is not one
        if (c.verb == "colour" && c.argument != "force" && c.argument != "speed" &&
            c.argument != "stress" && c.argument != "none") {
          throw std::invalid_argument("script: colour '" + c.argument +
                                      "': expected force, speed, stress or none");
        }
        break;
    }
    commands.push_back(c);
  }
  return commands;
}

}  // namespace granular::gui
