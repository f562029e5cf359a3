#include "command_line.hpp"

#include <iostream>
#include <sstream>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include "paper_figures.hpp"
#include "run_figures.hpp"

namespace granular::app {

namespace {

/// A number of the given unit that must be finite and > 0 (or >= 0): CLI11's own range checks
/// print their bound, DBL_MAX, with 309 digits.
CLI::Validator finiteNumber(const std::string& unit, bool zeroAllowed,
                            const std::string& zeroMeans) {
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        double value = 0;
        std::size_t used = 0;
        try {
          value = std::stod(text, &used);
        } catch (const std::exception&) {
          used = 0;
        }
        const bool ok = used == text.size() && used > 0 && std::isfinite(value) &&
                        (zeroAllowed ? value >= 0 : value > 0);
        if (ok) return {};
        return "'" + text + "' is not a finite number " + (zeroAllowed ? ">= 0" : "> 0") + " " +
               unit + zeroMeans;
      },
      zeroAllowed ? "NUMBER >= 0" : "NUMBER > 0");
}

/// A path that names something: `--out ""` would silently mean the default folder.
const CLI::Validator kNonEmptyPath(
    [](std::string& text) -> std::string {
      return text.empty() ? std::string("an empty path; leave the option out for the default")
                          : std::string();
    },
    "PATH");

/// Levenshtein distance, for "did you mean".
std::size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

}  // namespace

CommandLine::CommandLine(std::shared_ptr<const Communicator> ranks) : ranks_(std::move(ranks)) {
  app_.require_subcommand(1);

  runCommand_ = app_.add_subcommand("run", "Run every stage of a scene, writing its outputs");
  runCommand_->add_option("scene", run_.scene, "Scene file (TOML; keys in docs/scenes.md)")
      ->required();
  runCommand_->add_option("-o,--out", run_.outDir, "Output folder (default: runs/<scene stem>)")
      ->check(kNonEmptyPath);
  runCommand_->add_flag("-q,--quiet", run_.quiet, "No progress lines on stderr");
  runCommand_
      ->add_option("--checkpoint-every", run_.checkpointEvery,
                   "Wall-clock seconds between checkpoints (OUT/checkpoint.bin, also written at "
                   "each stage's end); 0: none")
      ->capture_default_str()
      ->check(finiteNumber("seconds", true, " (0: no checkpoints)"));
  runCommand_->add_flag("--resume", run_.resume,
                        "Continue from OUT/checkpoint.bin if it exists (bit for bit as if the run "
                        "had never stopped); otherwise start from the beginning");
  auto* force = runCommand_->add_flag(
      "--force", run_.force,
      "Start again in OUT even if it holds an earlier run: that run's files "
      "(time series, snapshots, ParaView files, checkpoint) are removed first");
  force->excludes("--resume");
  runCommand_->add_flag("--figures", run_.figures,
                        "At the end, draw the run's figures into OUT/figures/ as `granular figures "
                        "OUT` does");

  paper_.scenesDir = GRANULAR_SCENES_DIR;
  paperCommand_ = app_.add_subcommand(
      "paper",
      "Reproduce the paper: both friction cases, a constant-k_t sensitivity case, time series, "
      "stresses and report.md");
  paperCommand_->add_option("-o,--out", paper_.outDir, "Output folder (default: runs/paper)")
      ->check(kNonEmptyPath);
  paperCommand_
      ->add_option("--scenes", paper_.scenesDir,
                   "Folder of paper-mu0.toml and paper-mu03.toml (default: the installed "
                   "assets/scenes)")
      ->check(kNonEmptyPath);
  paperCommand_->add_flag("--force", paper_.force,
                          "Write into --out even if it holds other files and no paper run");
  paperCommand_->add_flag("--fresh", paper_.fresh,
                          "Settle again even if settled checkpoints exist");
  paperCommand_->add_flag("-q,--quiet", paper_.quiet, "No progress lines on stderr");
  CLI::Option* sensitivity = paperCommand_->add_flag(
      "--sensitivity", paper_.sensitivity,
      "Also run the mu = 0.3 case from --seeds initial states with both tangential laws (Mindlin "
      "and a constant k_t) and report their means and spreads; about 7 s a bed on 2 cores");
  paperCommand_
      ->add_option("--seeds", paper_.seeds,
                   "Initial states (grid seeds from the paper's) for --sensitivity (default " +
                       std::to_string(kSensitivitySeeds) + ")")
      ->check(CLI::Range(2, 1000))
      ->needs(sensitivity);

  calibrateCommand_ = app_.add_subcommand(
      "calibrate-box",
      "Settle stage 1 in square boxes of several sides; fit the side that gives "
      "a target settled height");
  calibrateCommand_->add_option("scene", calibrate_.scene, "Scene file (its first stage settles)")
      ->required();
  calibrateCommand_->add_option("--sides", calibrate_.sides, "Box sides to try [m]")
      ->required()
      ->delimiter(',')
      ->check(finiteNumber("m", false, ""));
  calibrateCommand_
      ->add_option("--target-height", calibrate_.targetHeight,
                   "Settled height to hit [m] (default 1.087, the paper's)")
      ->check(finiteNumber("m", false, ""));
  calibrateCommand_
      ->add_option("--report", calibrate_.report, "Also write the table here (markdown file)")
      ->check(kNonEmptyPath);
  calibrateCommand_->add_flag("-q,--quiet", calibrate_.quiet, "No progress lines on stderr");

  silo_.scene = std::filesystem::path(GRANULAR_SCENES_DIR) / "silo-study.toml";
  siloCommand_ = app_.add_subcommand(
      "silo",
      "The silo study: fill a silo by pouring, measure its wall pressures against Janssen's law, "
      "discharge it through four orifices against Beverloo's; report.md, tables and figures");
  siloCommand_->add_option("-o,--out", silo_.outDir, "Output folder (default: runs/silo)")
      ->check(kNonEmptyPath);
  siloCommand_
      ->add_option("--scene", silo_.scene,
                   "The silo scene (default: the installed silo-study.toml; its walls' names "
                   "are the study's, docs/guide.md)")
      ->check(kNonEmptyPath);
  siloCommand_
      ->add_option("--particles", silo_.particles,
                   "Particles poured in (default: the scene's, 10000); more for a taller bed")
      ->check(CLI::Range(std::uint64_t{100}, std::uint64_t{100'000'000}));
  siloCommand_
      ->add_option("--discharge-time", silo_.dischargeTime,
                   "Each orifice's discharge [s] (default 1)")
      ->check(CLI::Range(0.05, 1e4));
  siloCommand_->add_flag("-q,--quiet", silo_.quiet, "No progress lines on stderr");

  figuresCommand_ = app_.add_subcommand(
      "figures",
      "Draw the figures of a `granular run` folder, or re-draw every figure of a `granular "
      "paper` run, from its saved results");
  figuresCommand_
      ->add_option("run_dir", figuresDir_, "The --out folder of `granular run` or `granular paper`")
      ->required()
      ->check(kNonEmptyPath);
}

int CommandLine::run(int argc, char** argv) {
  // Under mpirun every rank parses alike; only rank 0 says what is wrong.
  const bool root = !ranks_ || ranks_->rank() == 0;
  std::ostringstream silenced;
  std::ostream& out = root ? std::cout : silenced;
  std::ostream& err = root ? std::cerr : silenced;
  // A mistyped command would otherwise be taken for a stray argument ("A subcommand is
  // required"): name it and the nearest command.
  const std::vector<CLI::App*> commands = app_.get_subcommands([](CLI::App*) { return true; });
  const auto named = [&](const CLI::App* c) { return argc > 1 && c->get_name() == argv[1]; };
  if (argc > 1 && argv[1][0] != '-' && std::none_of(commands.begin(), commands.end(), named)) {
    std::string nearest, all;
    std::size_t best = ~std::size_t{0};
    for (const CLI::App* command : commands) {
      const std::size_t d = editDistance(argv[1], command->get_name());
      if (d < best) best = d, nearest = command->get_name();
      all += (all.empty() ? "" : ", ") + command->get_name();
    }
    // The accuracy benchmark is a program of its own (bench/), so that no benchmark code is
    // part of `granular`; its name as a command says where it is.
    const std::string hint =
        std::string(argv[1]) == "bench-accuracy"
            ? "; the accuracy benchmark is the program granular_bench_accuracy "
              "(build/release/bench/granular_bench_accuracy --help)"
            : (best <= 2 ? "; did you mean '" + nearest + "'?" : std::string());
    err << "error: unknown command '" << argv[1] << "'" << hint << " (commands: " << all
        << "; granular --help)\n";
    return 2;
  }
  try {
    app_.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help exits 0; a usage error gets 2 like an invalid scene, the caller's mistake.
    return app_.exit(e, out, err) == 0 ? 0 : 2;
  }
  if (*runCommand_) {
    run_.ranks = ranks_;
    return runCommand(run_);
  }
  // The other commands run on one process: under mpirun, rank 0 alone, while the others wait
  // asleep (not polling: rank 0's threads keep every core).
  int code = 2;
  if (root) {
    if (*paperCommand_) code = paperCommand(paper_);
    if (*calibrateCommand_) code = calibrateCommand(calibrate_);
    if (*siloCommand_) code = siloCommand(silo_);
    if (*figuresCommand_) {
      code =
          isRunFolder(figuresDir_) ? runFiguresCommand(figuresDir_) : figuresCommand(figuresDir_);
    }
  } else {
    code = 0;
  }
  if (ranks_) ranks_->restingBarrier();
  return code;
}

}  // namespace granular::app
