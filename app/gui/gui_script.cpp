#include "gui_script.hpp"

#include <set>
#include <sstream>
#include <stdexcept>

namespace granular::gui {

std::vector<ScriptCommand> parseScript(const std::string& text) {
  static const std::set<std::string> bare = {"run", "pause", "reset", "stage2", "quit"};
  static const std::set<std::string> numeric = {"step",          "speed",   "mu",
                                                "gamma-n",       "gamma-t", "youngs-modulus",
                                                "wall-velocity", "frames",  "wait-steps"};
  static const std::set<std::string> word = {"colour",          "screenshot",     "load-checkpoint",
                                             "save-checkpoint", "export-figures", "save-view"};
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
    if (bare.count(c.verb)) {
      if (!c.argument.empty()) {
        throw std::invalid_argument("script: '" + c.verb + "' takes no argument");
      }
    } else if (numeric.count(c.verb)) {
      std::size_t used = 0;
      try {
        std::stod(c.argument, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (c.argument.empty() || used != c.argument.size()) {
        throw std::invalid_argument("script: '" + c.verb + "' needs a number, got '" + c.argument +
                                    "'");
      }
    } else if (word.count(c.verb)) {
      if (c.argument.empty()) throw std::invalid_argument("script: '" + c.verb + "' needs a value");
      if (c.verb == "colour" && c.argument != "force" && c.argument != "speed" &&
          c.argument != "stress" && c.argument != "none") {
        throw std::invalid_argument("script: colour '" + c.argument +
                                    "': expected force, speed, stress or none");
      }
    } else {
      throw std::invalid_argument(
          "script: unknown command '" + c.verb +
          "' (run, pause, reset, stage2, step N, speed N, mu X, gamma-n X, gamma-t X, "
          "youngs-modulus X, wall-velocity X, colour force|speed|stress|none, frames N, "
          "wait-steps N, screenshot FILE, load-checkpoint FILE, save-checkpoint FILE, "
          "save-view FILE, export-figures DIR, quit)");
    }
    commands.push_back(c);
  }
  return commands;
}

}  // namespace granular::gui
