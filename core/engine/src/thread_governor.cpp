/// The thread governor (thread_governor.hpp).
#include "thread_governor.hpp"

#include <algorithm>

namespace granular {

double ThreadGovernor::typical(const std::array<double, kWindow>& times) {
  // The mean: a busy machine's cost is in its tail of steps that waited a time slice for a
  // core. Without the slowest step, which a neighbour-list rebuild or a step check may be.
  double sum = 0.0, slowest = 0.0;
  for (double t : times) {
    sum += t;
    slowest = std::max(slowest, t);
  }
  return (sum - slowest) / double(kWindow - 1);
}

void ThreadGovernor::stepTook(double seconds) {
  if (!trialing_) {
    // The last kWindow steps at the current count: the reference a trial is judged against.
    reference_[stepsSinceTrial_ % kWindow] = seconds;
    ++stepsSinceTrial_;
    secondsSinceTrial_ += seconds;
    // Once the reference is of this count alone, and the trials' share of the time is small.
    if (stepsSinceTrial_ >= 2 * kWindow && secondsSinceTrial_ >= kShare * lastTrialSeconds_) {
      referenceTypical_ = typical(reference_);
      trialing_ = true;
      filled_ = 0;
      lastTrialSeconds_ = 0.0;
    }
    return;
  }
  trial_[filled_++] = seconds;
  lastTrialSeconds_ += seconds;
  if (filled_ < kWindow) return;
  if (typical(trial_) <= kMargin * referenceTypical_) current_ = other();
  trialing_ = false;
  stepsSinceTrial_ = 0;
  secondsSinceTrial_ = 0.0;
}

}  // namespace granular
