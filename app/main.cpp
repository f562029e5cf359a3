/// granular: the command line. Subcommands:
///   granular run SCENE.toml [--out DIR] [--quiet] [--checkpoint-every S] [--resume]
///   granular paper [--out DIR] [--scenes DIR] [--fresh] [--quiet]
///   granular figures RUN_DIR
///   granular calibrate-box SCENE.toml --sides A,B,C [--target-height H] [--report FILE]
///   granular bench-accuracy [--run DIR] [--out DIR] [--scenes DIR] [--quick]
/// Exit status: 0 done, 1 I/O error, 2 invalid scene or configuration (or bad arguments),
/// 3 the simulation's state broke (NaN or infinity; `run` names the step and the particle).
#include <CLI/CLI.hpp>

#include "bench_accuracy_command.hpp"
#include "calibrate_command.hpp"
#include "paper_command.hpp"
#include "paper_figures.hpp"
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
  runCommand
      ->add_option("--checkpoint-every", run.checkpointEvery,
                   "Wall-clock seconds between checkpoints (OUT/checkpoint.bin, also written at "
                   "each stage's end); 0: none")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  runCommand->add_flag("--resume", run.resume,
                       "Continue from OUT/checkpoint.bin if it exists (bit for bit as if the run "
                       "had never stopped); otherwise start from the beginning");

  granular::app::PaperOptions paper;
  paper.scenesDir = GRANULAR_SCENES_DIR;
  CLI::App* paperCommand = app.add_subcommand(
      "paper", "Reproduce the paper: both friction cases, time series, stresses and report.md");
  paperCommand->add_option("-o,--out", paper.outDir, "Output folder (default: runs/paper)");
  paperCommand->add_option("--scenes", paper.scenesDir,
                           "Folder of paper-mu0.toml and paper-mu03.toml (default: the installed "
                           "assets/scenes)");
  paperCommand->add_flag("--fresh", paper.fresh, "Settle again even if settled checkpoints exist");
  paperCommand->add_flag("-q,--quiet", paper.quiet, "No progress lines on stderr");

  granular::app::CalibrateOptions calibrate;
  CLI::App* calibrateCommand =
      app.add_subcommand("calibrate-box",
                         "Settle stage 1 in square boxes of several sides; fit the side that gives "
                         "a target settled height");
  calibrateCommand->add_option("scene", calibrate.scene, "Scene file (its first stage settles)")
      ->required();
  calibrateCommand->add_option("--sides", calibrate.sides, "Box sides to try [m]")
      ->required()
      ->delimiter(',');
  calibrateCommand->add_option("--target-height", calibrate.targetHeight,
                               "Settled height to hit [m] (default 1.087, the paper's)");
  calibrateCommand->add_option("--report", calibrate.report,
                               "Also write the table here (markdown)");
  calibrateCommand->add_flag("-q,--quiet", calibrate.quiet, "No progress lines on stderr");

  std::filesystem::path figuresDir;
  CLI::App* figuresCommand = app.add_subcommand(
      "figures", "Re-draw every figure of a `granular paper` run from its saved results");
  figuresCommand->add_option("run_dir", figuresDir, "The --out folder of `granular paper`")
      ->required();

  granular::app::BenchAccuracyOptions bench;
  bench.scenesDir = GRANULAR_SCENES_DIR;
  CLI::App* benchCommand = app.add_subcommand(
      "bench-accuracy",
      "Speed against error of Gear5 and velocity Verlet: impacts and the paper's stage 2");
  benchCommand->add_option("--run", bench.runDir,
                           "`granular paper --out` folder with the settled checkpoints (default: "
                           "runs/paper)");
  benchCommand->add_option("-o,--out", bench.outDir,
                           "Output folder (default: runs/bench-accuracy, with --quick "
                           "runs/bench-accuracy-quick)");
  benchCommand->add_option("--scenes", bench.scenesDir,
                           "Folder of paper-mu0.toml and paper-mu03.toml (default: the installed "
                           "assets/scenes)");
  benchCommand->add_flag("--quick", bench.quick,
                         "Smoke run (about 15 s): fewer steps, μ = 0.3 only, stage 2 cut to 0.3 s");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help exits 0; a usage error gets 2 like an invalid scene, the caller's mistake.
    return app.exit(e) == 0 ? 0 : 2;
  }
  if (*runCommand) return granular::app::runCommand(run);
  if (*paperCommand) return granular::app::paperCommand(paper);
  if (*calibrateCommand) return granular::app::calibrateCommand(calibrate);
  if (*figuresCommand) return granular::app::figuresCommand(figuresDir);
  if (*benchCommand) {
    // A smoke run must not overwrite the results of a full one.
    if (bench.quick && benchCommand->count("--out") == 0)
      bench.outDir = "runs/bench-accuracy-quick";
    return granular::app::benchAccuracyCommand(bench);
  }
  return 2;
}
