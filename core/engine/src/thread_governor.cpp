/// The thread governor (thread_governor.hpp).
#include "thread_governor.hpp"

#include <algorithm>

namespace granular {

double ThreadGovernor::median(std::array<double, kWindow> times) {
  std::nth_element(times.begin(), times.begin() + kWindow / 2, times.end());
  return times[kWindow / 2];
}

void ThreadGovernor::stepTook(double seconds) {
  if (!trialing_) {
    // The last kWindow steps at the current count: the reference a trial is judged against.
    reference_[stepsSinceTrial_ % kWindow] = seconds;
    ++stepsSinceTrial_;
    // The first trial as soon as a reference is whole; then every kPeriod steps.
    const bool first = referenceMedian_ == 0.0 && stepsSinceTrial_ >= 2 * kWindow;
    if (first || stepsSinceTrial_ >= kPeriod) {
      referenceMedian_ = median(reference_);
      trialing_ = true;
      filled_ = 0;
    }
    return;
  }
  trial_[filled_++] = seconds;
  if (filled_ < kWindow) return;
  if (median(trial_) <= kMargin * referenceMedian_) current_ = other();
  trialing_ = false;
  stepsSinceTrial_ = 0;
}

}  // namespace granular
