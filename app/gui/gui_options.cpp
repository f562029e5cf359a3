#include "gui_options.hpp"

#include <stdexcept>

#include "gui_script.hpp"

namespace granular::gui {

namespace {

constexpr long kMaxFrames = 100000000;
constexpr int kMinWidth = 640, kMinHeight = 480, kMaxSide = 8192;

/// Wraps `words` at `width` columns, each line after the first indented by `indent` spaces.
std::string wrap(const std::string& words, std::size_t width, std::size_t indent) {
  std::string out, line;
  std::size_t start = 0;
  while (start < words.size()) {
    std::size_t end = words.find(' ', start);
    if (end == std::string::npos) end = words.size();
    const std::string word = words.substr(start, end - start);
    if (!line.empty() && line.size() + 1 + word.size() > width) {
      out += line + "\n" + std::string(indent, ' ');
      line.clear();
    }
    line += (line.empty() ? "" : " ") + word;
    start = end + 1;
  }
  return out + line;
}

}  // namespace

const std::vector<GuiOptionSpec>& guiOptionSpecs() {
  static const std::vector<GuiOptionSpec> specs = {
      {"--scene", "FILE", "scene to load (default: the paper's mu = 0.3 case)"},
      {"--frames", "N",
       "quit after N frames, N in [1, " + std::to_string(kMaxFrames) + "] (scripted runs)"},
      {"--screenshot", "FILE", "write the window as a PNG when quitting"},
      {"--script", "TEXT", "commands separated by ';', one per frame (below)"},
      {"--width", "PX",
       "window width in [" + std::to_string(kMinWidth) + ", " + std::to_string(kMaxSide) +
           "] (default 1280)"},
      {"--height", "PX",
       "window height in [" + std::to_string(kMinHeight) + ", " + std::to_string(kMaxSide) +
           "] (default 800)"},
      {"--help", "", "print this help and exit"},
  };
  return specs;
}

std::string guiUsage() {
  std::string usage = "usage: granular-gui";
  for (const GuiOptionSpec& s : guiOptionSpecs()) {
    usage += " [" + s.name + (s.placeholder.empty() ? "" : " " + s.placeholder) + "]";
  }
  usage = wrap(usage, 96, 20) + "\n";
  for (const GuiOptionSpec& s : guiOptionSpecs()) {
    std::string head = "  " + s.name + (s.placeholder.empty() ? "" : " " + s.placeholder);
    head.resize(21, ' ');
    usage += head + wrap(s.help, 75, 21) + "\n";
  }
  usage += "Script commands: " + wrap(scriptSyntax(), 80, 17) + "\n";
  usage += "Mouse in the 3-D view: left drag orbits, right drag pans, the wheel zooms.\n";
  return usage;
}

bool parseGuiOptions(int argc, const char* const* argv, GuiOptions& o, std::ostream& help) {
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    auto value = [&]() -> std::string {
      if (a + 1 >= argc) throw std::invalid_argument(arg + " needs a value");
      return argv[++a];
    };
    auto integer = [&](long lo, long hi) {
      const std::string v = value();
      std::size_t used = 0;
      long n = 0;
      try {
        n = std::stol(v, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != v.size() || n < lo || n > hi) {
        throw std::invalid_argument(arg + " " + v + ": expected an integer in [" +
                                    std::to_string(lo) + ", " + std::to_string(hi) + "]");
      }
      return n;
    };
    if (arg == "-h" || arg == "--help") {
      help << guiUsage();
      return false;
    } else if (arg == "--scene") {
      o.scene = value();
    } else if (arg == "--frames") {
      o.frames = integer(1, kMaxFrames);
    } else if (arg == "--screenshot") {
      o.screenshot = value();
    } else if (arg == "--script") {
      o.script = value();
    } else if (arg == "--width") {
      o.width = int(integer(kMinWidth, kMaxSide));
    } else if (arg == "--height") {
      o.height = int(integer(kMinHeight, kMaxSide));
    } else {
      throw std::invalid_argument("unknown option '" + arg + "' (try --help)");
    }
  }
  return true;
}

}  // namespace granular::gui
