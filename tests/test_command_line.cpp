/// The command lines' help and their reference in docs/guide.md §8 (issue 9): `granular COMMAND
/// --help` and `granular-gui --help` list every option each program accepts, with its meaning,
/// and the guide documents exactly those options, so neither can drift from the code. The options
/// come from the programs' own tables (CLI11's tree in command_line.cpp, the GUI's option and
/// script-verb tables), not from a list kept here.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "command_line.hpp"
#include "gui_options.hpp"
#include "gui_script.hpp"

namespace {

using granular::app::CommandLine;

/// The text of docs/guide.md under the heading "### `TITLE`", up to the next heading.
std::string guideSection(const std::string& title) {
  std::ifstream in(std::filesystem::path(GRANULAR_SOURCE_DIR) / "docs/guide.md");
  EXPECT_TRUE(in) << "docs/guide.md missing";
  std::string line, text;
  bool inside = false;
  while (std::getline(in, line)) {
    if (line.rfind("#", 0) == 0) {
      if (inside) break;
      inside = line == "### `" + title + "`";
      continue;
    }
    if (inside) text += line + "\n";
  }
  EXPECT_FALSE(text.empty()) << "docs/guide.md has no section ### `" << title << "`";
  return text;
}

/// Every "--name" token in `text` (a name starts with a lower-case letter and goes on with
/// lower-case letters, digits and dashes). Scanned by hand: GCC 12's <regex> trips
/// -Wmaybe-uninitialized under the sanitizer build's -Werror.
std::set<std::string> longOptionsIn(const std::string& text) {
  const auto lower = [](char c) { return c >= 'a' && c <= 'z'; };
  const auto nameChar = [&](char c) { return lower(c) || (c >= '0' && c <= '9') || c == '-'; };
  std::set<std::string> names;
  std::size_t i = 0;
  while (i + 2 < text.size()) {
    if (text[i] == '-' && text[i + 1] == '-' && lower(text[i + 2])) {
      std::size_t end = i + 3;
      while (end < text.size() && nameChar(text[end])) ++end;
      names.insert(text.substr(i, end - i));
      i = end;
    } else {
      ++i;
    }
  }
  return names;
}

std::string upper(std::string s) {
  for (char& c : s) c = char(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

std::vector<CLI::App*> subcommands(CommandLine& cli) {
  return cli.app().get_subcommands([](CLI::App*) { return true; });
}

TEST(CommandLine, EverySubcommandIsDocumentedAndDescribed) {
  CommandLine cli;
  const std::vector<CLI::App*> commands = subcommands(cli);
  ASSERT_GE(commands.size(), 4u);  // run, paper, figures, calibrate-box
  const std::string mainHelp = cli.app().help();
  for (CLI::App* command : commands) {
    SCOPED_TRACE(command->get_name());
    EXPECT_FALSE(command->get_description().empty());
    EXPECT_NE(mainHelp.find(command->get_name()), std::string::npos);
    guideSection("granular " + command->get_name());
  }
}

TEST(CommandLine, EachSubcommandsHelpListsEveryOptionWithItsMeaning) {
  CommandLine cli;
  for (CLI::App* command : subcommands(cli)) {
    const std::string help = command->help();
    for (const CLI::Option* option : command->get_options()) {
      SCOPED_TRACE(command->get_name() + " " + option->get_name());
      EXPECT_FALSE(option->get_description().empty()) << "an option without a meaning";
      for (const std::string& name : option->get_lnames()) {
        EXPECT_NE(help.find("--" + name), std::string::npos);
      }
      for (const std::string& name : option->get_snames()) {
        EXPECT_NE(help.find("-" + name + ","), std::string::npos);
      }
      if (option->get_positional()) {
        EXPECT_NE(help.find(option->get_name(true, false)), std::string::npos);
      }
      EXPECT_NE(help.find(option->get_description().substr(0, 20)), std::string::npos);
    }
  }
}

/// What is wrong between `command`'s options and its reference `section`: each message names an
/// option that one has and the other lacks.
std::vector<std::string> referenceProblems(CLI::App* command, const std::string& section) {
  std::vector<std::string> problems;
  std::set<std::string> accepted = {"--help"};
  for (const CLI::Option* option : command->get_options()) {
    if (option == command->get_help_ptr()) continue;
    for (const std::string& name : option->get_lnames()) {
      accepted.insert("--" + name);
      if (section.find("--" + name) == std::string::npos) {
        problems.push_back("--" + name + " is not documented");
      }
    }
    for (const std::string& name : option->get_snames()) {
      if (section.find("`-" + name + ", --") == std::string::npos) {
        problems.push_back("-" + name + " is not documented");
      }
    }
    if (option->get_positional()) {
      const std::string placeholder = "`" + upper(option->get_name(true, false)) + "`";
      if (section.find(placeholder) == std::string::npos) {
        problems.push_back(placeholder + " is not documented");
      }
    }
  }
  for (const std::string& name : longOptionsIn(section)) {
    if (!accepted.count(name)) problems.push_back(name + " is documented but not accepted");
  }
  return problems;
}

TEST(CommandLine, TheGuideDocumentsExactlyTheOptionsEachSubcommandAccepts) {
  CommandLine cli;
  for (CLI::App* command : subcommands(cli)) {
    const std::vector<std::string> problems =
        referenceProblems(command, guideSection("granular " + command->get_name()));
    EXPECT_TRUE(problems.empty()) << "granular " << command->get_name() << ": "
                                  << testing::PrintToString(problems);
  }
}

TEST(CommandLine, TheReferenceCheckCanFail) {
  CommandLine cli;
  CLI::App* run = cli.app().get_subcommand("run");
  const std::string section = guideSection("granular run");
  ASSERT_TRUE(referenceProblems(run, section).empty());
  // An option the guide lacks, and one the guide documents that the program lacks.
  run->add_flag(std::string("--not-documented"))->description("new");
  EXPECT_EQ(referenceProblems(run, section + "| `--bogus DIR` | x |\n"),
            (std::vector<std::string>{"--not-documented is not documented",
                                      "--bogus is documented but not accepted"}));
}

TEST(CommandLine, HelpExitsZeroAndABadOptionExitsTwo) {
  const char* help[] = {"granular", "run", "--help"};
  const char* bad[] = {"granular", "paper", "--no-such-option"};
  const char* none[] = {"granular"};
  testing::internal::CaptureStdout();
  testing::internal::CaptureStderr();
  CommandLine a, b, c;
  EXPECT_EQ(a.run(3, const_cast<char**>(help)), 0);
  EXPECT_EQ(b.run(3, const_cast<char**>(bad)), 2);
  EXPECT_EQ(c.run(1, const_cast<char**>(none)), 2);
  const std::string out = testing::internal::GetCapturedStdout();
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(out.find("--checkpoint-every"), std::string::npos);
  EXPECT_NE(err.find("--no-such-option"), std::string::npos);
}

TEST(CommandLine, BenchAccuracyIsNoCommandAndNamesTheBenchmarkProgram) {
  CommandLine cli;
  EXPECT_EQ(cli.app()
                .get_subcommands([](CLI::App* c) { return c->get_name() == "bench-accuracy"; })
                .size(),
            0u);
  const char* old[] = {"granular", "bench-accuracy", "--quick"};
  testing::internal::CaptureStderr();
  EXPECT_EQ(cli.run(3, const_cast<char**>(old)), 2);
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("unknown command 'bench-accuracy'"), std::string::npos) << err;
  EXPECT_NE(err.find("granular_bench_accuracy"), std::string::npos) << err;
}

TEST(GuiCommandLine, HelpListsEveryOptionAndScriptCommand) {
  const std::string usage = granular::gui::guiUsage();
  for (const auto& spec : granular::gui::guiOptionSpecs()) {
    SCOPED_TRACE(spec.name);
    EXPECT_NE(usage.find(spec.name), std::string::npos);
    EXPECT_FALSE(spec.help.empty());
    EXPECT_NE(usage.find(spec.help.substr(0, 20)), std::string::npos);
  }
  for (const std::string& verb : granular::gui::scriptVerbs()) {
    EXPECT_NE(usage.find(verb), std::string::npos) << verb;
  }
}

TEST(GuiCommandLine, EveryListedOptionIsAcceptedAndOthersAreRefused) {
  for (const auto& spec : granular::gui::guiOptionSpecs()) {
    SCOPED_TRACE(spec.name);
    const std::string value = spec.placeholder == "N"    ? "10"
                              : spec.placeholder == "PX" ? "800"
                                                         : "x";
    std::vector<const char*> argv = {"granular-gui", spec.name.c_str()};
    if (!spec.placeholder.empty()) argv.push_back(value.c_str());
    granular::gui::GuiOptions options;
    std::ostringstream help;
    bool proceed = false;
    EXPECT_NO_THROW(
        proceed = granular::gui::parseGuiOptions(int(argv.size()), argv.data(), options, help));
    EXPECT_EQ(proceed, spec.name != "--help");
    EXPECT_EQ(help.str().empty(), spec.name != "--help");
  }
  const char* unknown[] = {"granular-gui", "--colour"};
  const char* tooSmall[] = {"granular-gui", "--width", "100"};
  granular::gui::GuiOptions options;
  std::ostringstream help;
  try {
    granular::gui::parseGuiOptions(2, unknown, options, help);
    ADD_FAILURE() << "an unknown option was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("unknown option '--colour'"), std::string::npos);
  }
  try {
    granular::gui::parseGuiOptions(3, tooSmall, options, help);
    ADD_FAILURE() << "a width below the minimum was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("[640, 8192]"), std::string::npos) << e.what();
  }
}

TEST(GuiCommandLine, TheGuideDocumentsExactlyTheWindowsOptionsAndScriptCommands) {
  const std::string section = guideSection("granular-gui");
  std::set<std::string> accepted;
  for (const auto& spec : granular::gui::guiOptionSpecs()) {
    accepted.insert(spec.name);
    EXPECT_NE(section.find("`" + spec.name), std::string::npos) << spec.name;
  }
  for (const std::string& name : longOptionsIn(section)) {
    EXPECT_TRUE(accepted.count(name))
        << "docs/guide.md documents " << name << ", which granular-gui does not accept";
  }
  for (const std::string& verb : granular::gui::scriptVerbs()) {
    EXPECT_NE(section.find("`" + verb), std::string::npos) << "script command " << verb;
  }
}

}  // namespace
