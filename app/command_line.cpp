#include "command_line.hpp"

#include "paper_figures.hpp"

namespace granular::app {

CommandLine::CommandLine() {
  app_.require_subcommand(1);

  runCommand_ = app_.add_subcommand("run", "Run every stage of a scene, writing its outputs");
  runCommand_->add_option("scene", run_.scene, "Scene file (TOML; keys in docs/scenes.md)")
      ->required();
  runCommand_->add_option("-o,--out", run_.outDir, "Output folder (default: runs/<scene stem>)");
  runCommand_->add_flag("-q,--quiet", run_.quiet, "No progress lines on stderr");
  runCommand_
      ->add_option("--checkpoint-every", run_.checkpointEvery,
                   "Wall-clock seconds between checkpoints (OUT/checkpoint.bin, also written at "
                   "each stage's end); 0: none")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  runCommand_->add_flag("--resume", run_.resume,
                        "Continue from OUT/checkpoint.bin if it exists (bit for bit as if the run "
                        "had never stopped); otherwise start from the beginning");

  paper_.scenesDir = GRANULAR_SCENES_DIR;
  paperCommand_ = app_.add_subcommand(
      "paper", "Reproduce the paper: both friction cases, time series, stresses and report.md");
  paperCommand_->add_option("-o,--out", paper_.outDir, "Output folder (default: runs/paper)");
  paperCommand_->add_option("--scenes", paper_.scenesDir,
                            "Folder of paper-mu0.toml and paper-mu03.toml (default: the installed "
                            "assets/scenes)");
  paperCommand_->add_flag("--fresh", paper_.fresh,
                          "Settle again even if settled checkpoints exist");
  paperCommand_->add_flag("-q,--quiet", paper_.quiet, "No progress lines on stderr");

  calibrateCommand_ = app_.add_subcommand(
      "calibrate-box",
      "Settle stage 1 in square boxes of several sides; fit the side that gives "
      "a target settled height");
  calibrateCommand_->add_option("scene", calibrate_.scene, "Scene file (its first stage settles)")
      ->required();
  calibrateCommand_->add_option("--sides", calibrate_.sides, "Box sides to try [m]")
      ->required()
      ->delimiter(',');
  calibrateCommand_->add_option("--target-height", calibrate_.targetHeight,
                                "Settled height to hit [m] (default 1.087, the paper's)");
  calibrateCommand_->add_option("--report", calibrate_.report,
                                "Also write the table here (markdown)");
  calibrateCommand_->add_flag("-q,--quiet", calibrate_.quiet, "No progress lines on stderr");

  figuresCommand_ = app_.add_subcommand(
      "figures", "Re-draw every figure of a `granular paper` run from its saved results");
  figuresCommand_->add_option("run_dir", figuresDir_, "The --out folder of `granular paper`")
      ->required();

  bench_.scenesDir = GRANULAR_SCENES_DIR;
  benchCommand_ = app_.add_subcommand(
      "bench-accuracy",
      "Speed against error of Gear5 and velocity Verlet: impacts and the paper's stage 2");
  benchCommand_->add_option("--run", bench_.runDir,
                            "`granular paper --out` folder with the settled checkpoints (default: "
                            "runs/paper)");
  benchCommand_->add_option("-o,--out", bench_.outDir,
                            "Output folder (default: runs/bench-accuracy, with --quick "
                            "runs/bench-accuracy-quick)");
  benchCommand_->add_option("--scenes", bench_.scenesDir,
                            "Folder of paper-mu0.toml and paper-mu03.toml (default: the installed "
                            "assets/scenes)");
  benchCommand_->add_flag(
      "--quick", bench_.quick,
      "Smoke run (about 15 s): fewer steps, μ = 0.3 only, stage 2 cut to 0.3 s");
}

int CommandLine::run(int argc, char** argv) {
  try {
    app_.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help exits 0; a usage error gets 2 like an invalid scene, the caller's mistake.
    return app_.exit(e) == 0 ? 0 : 2;
  }
  if (*runCommand_) return runCommand(run_);
  if (*paperCommand_) return paperCommand(paper_);
  if (*calibrateCommand_) return calibrateCommand(calibrate_);
  if (*figuresCommand_) return figuresCommand(figuresDir_);
  if (*benchCommand_) {
    // A smoke run must not overwrite the results of a full one.
    if (bench_.quick && benchCommand_->count("--out") == 0)
      bench_.outDir = "runs/bench-accuracy-quick";
    return benchAccuracyCommand(bench_);
  }
  return 2;
}

}  // namespace granular::app
