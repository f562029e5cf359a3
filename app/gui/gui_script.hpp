#pragma once
/// Scripted mode: the buttons pressed from a command line, for tests and demos.
///
/// A script is commands separated by ';', carried out one per frame in order:
///   run | pause | reset | stage2 | step N | speed N (steps per update) | mu X | gamma-n X |
///   gamma-t X | youngs-modulus X | material KEY=X (any number parameter the contact model
///   declares, granular/contact_model.hpp) | wall-velocity X (m/s) | colour force|speed|stress|none
///   | frames N (wait N frames) | wait-steps N (wait until N more steps are done) | screenshot FILE
///   (the window) | save-view FILE (the 3-D view, 2× its size) | load-checkpoint FILE |
///   save-checkpoint FILE | export-figures DIR | quit
#include <string>
#include <vector>

#include "granular/contact_model.hpp"

namespace granular::gui {

/// `material KEY=X`: the declared parameter and its value.
struct MaterialSetting {
  const ParameterSpec* parameter;
  double value;
};
/// Parses KEY=X; throws std::invalid_argument naming the keys or the allowed range.
MaterialSetting materialSetting(const std::string& argument);

struct ScriptCommand {
  std::string verb;
  std::string argument;  ///< empty for verbs without one
};

/// Every verb the parser accepts, in the order the help lists them.
std::vector<std::string> scriptVerbs();

/// The verbs with their arguments ("run, pause, …, step N, …"), for --help and error messages.
std::string scriptSyntax();

/// Parses `text`; throws std::invalid_argument naming the bad command and what was expected.
std::vector<ScriptCommand> parseScript(const std::string& text);

}  // namespace granular::gui
