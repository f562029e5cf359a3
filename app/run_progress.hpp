#pragma once
/// What `granular run` stores with each checkpoint besides the simulation: which stage it is in,
/// how far that stage has run, how much of the time series is written, and how the finished
/// stages ended. Stored as text in the checkpoint's caller data, numbers as hexadecimal floats
/// so that a resumed run continues bit for bit.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "granular/stage.hpp"

namespace granular::app {

struct FinishedStage {
  StageResult result;
  double wallSeconds = 0.0;
};

/// A snapshot's ParaView files: which stage, the step they were written at, and the time since
/// the run began (the collections' time) [s].
struct ParaviewFrame {
  std::size_t stage = 0;
  std::uint64_t step = 0;
  double runTime = 0.0;
};

struct RunProgress {
  std::size_t stage = 0;                ///< index of the running stage (= count when complete)
  StageProgress inStage;                ///< how far that stage has run
  std::uint64_t seriesBytes = 0;        ///< length of timeseries.csv at the checkpoint [B]
  std::vector<FinishedStage> finished;  ///< the stages before `stage`
  /// The energy balance's total at the start of the run (RunChecks), so that a resumed run
  /// measures the drift from the same start; absent in checkpoints written before it was kept
  /// [J].
  std::optional<double> energyReference;
  /// FNV-1a of timeseries.csv's first `seriesBytes` bytes: a resumed run continues only the
  /// rows it wrote itself; absent in checkpoints written before it was kept.
  std::optional<std::uint64_t> seriesHash;
  /// The running stage's t = 0 on the simulation's clock [s] (its frames' times count from it).
  double stageOrigin = 0.0;
  /// The snapshots' ParaView frames written so far, in order: the .pvd collections list these
  /// and no others (files of another run in the folder, or written after the checkpoint by a
  /// life that was killed, are not this run's).
  std::vector<ParaviewFrame> frames;
};

std::string encodeRunProgress(const RunProgress& progress);
/// Throws CheckpointError (naming `file`) on text that is not a progress record.
RunProgress decodeRunProgress(const std::string& text, const std::string& file);

}  // namespace granular::app
