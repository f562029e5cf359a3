#pragma once
/// granular-gui's command line. One table gives both the parser and --help, so the help lists
/// every option the window accepts (a test walks the table and docs/guide.md against it).
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

namespace granular::gui {

struct GuiOptions {
  std::filesystem::path scene;  ///< the caller sets the default (the paper's μ = 0.3 case)
  long frames = -1;             ///< quit after this many frames; -1: never
  std::filesystem::path screenshot;
  std::string script;
  int width = 1280, height = 800;
};

struct GuiOptionSpec {
  std::string name;         ///< "--scene"
  std::string placeholder;  ///< "FILE"
  std::string help;
};

/// Every option the parser accepts, --help included.
const std::vector<GuiOptionSpec>& guiOptionSpecs();

/// The --help text: usage line, each option with its help, the script's verbs, the mouse.
std::string guiUsage();

/// Fills `options` from argv. Returns false when --help was asked (the usage is written to
/// `help`); throws std::invalid_argument naming the option and the allowed range on bad input.
bool parseGuiOptions(int argc, const char* const* argv, GuiOptions& options, std::ostream& help);

}  // namespace granular::gui
