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

struct RunProgress {
  std::size_t stage = 0;                ///< index of the running stage (= count when complete)
  StageProgress inStage;                ///< how far that stage has run
  std::uint64_t seriesBytes = 0;        ///< length of timeseries.csv at the checkpoint [B]
  std::vector<FinishedStage> finished;  ///< the stages before `stage`
  /// The energy balance's total at the start of the run (RunChecks), so that a resumed run
  /// measures the drift from the same start; absent in checkpoints written before it was kept
  /// [J].
  std::optional<double> energyReference;
};

std::string encodeRunProgress(const RunProgress& progress);
/// Throws CheckpointError (naming `file`) on text that is not a progress record.
RunProgress decodeRunProgress(const std::string& text, const std::string& file);

}  // namespace granular::app
