/// granular: the command line. Subcommands:
///   granular run SCENE.toml [--out DIR] [--quiet]
/// Exit status: 0 done, 1 I/O error, 2 invalid scene or configuration (or bad arguments).
#include <CLI/CLI.hpp>

#include "run_command.hpp"

int main(int argc, char** argv) {
  CLI::App app{"granular: discrete-element simulation of spheres in a box"};
  app.require_subcommand(1);

  granular::app::RunOptions run;
  CLI::App* runCommand =
      app.add_subcommand("run", "Run every stage of a scene, writing its outputs");
  runCommand->add_option("scene", run.scene, "Scene file (TOML; keys in docs/scenes.md)")
      ->required();
  runCommand->add_option("-o,--out", run.outDir, "Output folder (default: runs/<scene stem>)");
  runCommand->add_flag("-q,--quiet", run.quiet, "No progress lines on stderr");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help exits 0; a usage error gets 2 like an invalid scene, the caller's mistake.
    return app.exit(e) == 0 ? 0 : 2;
  }
  if (*runCommand) return granular::app::runCommand(run);
  return 2;
}
