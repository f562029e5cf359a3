#pragma once
/// How many threads a run left to OpenMP's default count (SimulationConfig::threads = 0) steps
/// with: all, or one, whichever steps faster now, by timing them. On a machine whose cores are
/// busy with other work, a thread waiting at a barrier spins on a core the thread it waits for
/// needs, and the other program takes turns with both: a run of two threads became six times
/// slower beside one busy process, where one thread, with a core to itself, is only as slow as
/// one thread is (bench/RESULTS.md, "A busy machine"). Now and then the governor times kWindow
/// steps with the other count and keeps the faster (their mean step against that of the last
/// kWindow steps, each without its slowest step, by a margin). A trial comes once the steps since
/// the last one have taken kShare times as long as that trial did: the trials cost a small, fixed
/// share of the run whether a step takes microseconds or seconds, and a wrong choice lasts that
/// long at most. The results are the same bits for any count, so the choice changes only the time
/// taken.
#include <array>
#include <cstddef>
#include <cstdint>

namespace granular {

class ThreadGovernor {
 public:
  /// Steps a trial (or its reference) times.
  static constexpr std::size_t kWindow = 15;
  /// The steps between two trials take at least this many times as long as the last trial.
  static constexpr double kShare = 40.0;
  /// The other count is taken when its typical step is this fraction of the current one's or
  /// less: a trial must be clearly faster, not faster by the noise of a busy machine.
  static constexpr double kMargin = 0.9;

  /// The count for the next step: 0 (all of OpenMP's threads) or 1.
  int threads() const { return trialing_ ? other() : current_; }
  /// After a step taken with threads(): its wall time [s].
  void stepTook(double seconds);
  /// Whether a trial is under way (for the tests).
  bool trialing() const { return trialing_; }
  /// Steps with `count` (0: all, or 1) from now on until the next trial (for the tests, which
  /// switch at will to see the same bits).
  void choose(int count) {
    current_ = count;
    trialing_ = false;
  }

 private:
  int other() const { return current_ == 0 ? 1 : 0; }
  /// A window's typical step: its mean without its slowest step [s].
  static double typical(const std::array<double, kWindow>& times);

  int current_ = 0;  ///< the count stepped with between trials: 0 (all) or 1
  bool trialing_ = false;
  std::size_t stepsSinceTrial_ = 0;
  double secondsSinceTrial_ = 0.0;           ///< the steps' time since the last trial [s]
  double lastTrialSeconds_ = 0.0;            ///< the last trial's steps' time [s]
  std::size_t filled_ = 0;                   ///< steps of the trial so far
  std::array<double, kWindow> reference_{};  ///< the last steps at current_ [s]
  std::array<double, kWindow> trial_{};      ///< the trial's steps [s]
  double referenceTypical_ = 0.0;
};

}  // namespace granular
