/// granular: the command line. Subcommands:
///   granular run SCENE.toml [--out DIR] [--quiet] [--checkpoint-every S] [--resume]
///   granular paper [--out DIR] [--scenes DIR] [--fresh] [--quiet]
///   granular figures RUN_DIR
///   granular calibrate-box SCENE.toml --sides A,B,C [--target-height H] [--report FILE]
///   granular bench-accuracy [--run DIR] [--out DIR] [--scenes DIR] [--quick]
/// The options live in command_line.cpp; docs/guide.md §8 lists them (a test keeps it true).
#include "command_line.hpp"

int main(int argc, char** argv) {
  granular::app::CommandLine commandLine;
  return commandLine.run(argc, argv);
}
