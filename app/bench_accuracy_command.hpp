#pragma once
/// `granular bench-accuracy`: speed against error of Gear5 and velocity Verlet. At several time
/// steps, each integrator's wall time and its error against a reference run at a much smaller
/// step, on a Hooke and a Hertz two-sphere impact (restitution, duration) and on σ33(t) of the
/// paper's stage 2 restored from the settled checkpoints of `granular paper`. Writes a CSV of
/// every run, a markdown summary and an error-against-wall-time figure.
#include <filesystem>

namespace granular::app {

struct BenchAccuracyOptions {
  std::filesystem::path runDir = "runs/paper";  ///< `granular paper --out` folder (checkpoints)
  std::filesystem::path outDir = "runs/bench-accuracy";  ///< where the results go
  std::filesystem::path scenesDir;  ///< folder of paper-mu0.toml, paper-mu03.toml
  /// Fewer steps, a coarser reference, stage 2 of μ = 0.3 only and cut to 0.3 s: a smoke run
  /// of about 15 s, not a result.
  bool quick = false;
};

/// Exit status: 0 done, 1 I/O error, 2 missing or unusable checkpoint, bad scene or option.
int benchAccuracyCommand(const BenchAccuracyOptions& options);

}  // namespace granular::app
