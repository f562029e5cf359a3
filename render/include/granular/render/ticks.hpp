#pragma once
/// Axis ticks: "nice" positions (multiples of 1, 2 or 5 × 10^k) and labels without floating-point
/// noise (0.3, not 0.30000000000000004), with U+2212 for minus and a power of ten factored out of
/// very large or very small values (shown once as "×10³"); on a logarithmic axis, the powers of
/// ten labelled as such ("10⁻⁴").
#include <string>
#include <vector>

namespace granular::render {

struct Ticks {
  std::vector<double> values;       ///< positions inside the range, ascending [data units]
  std::vector<std::string> labels;  ///< one per value, divided by 10^exponent
  /// Spacing between values [data units]; on a logarithmic axis, the decades between labelled
  /// powers of ten (0 on a short range labelled at 1, 2, 5 × 10^k).
  double step = 0.0;
  int exponent = 0;  ///< labels show value / 10^exponent; a multiple of 3
  /// Unlabelled, shorter ticks between the values: on a logarithmic axis 2–9 × 10^k [data units]
  std::vector<double> minor;
  /// "×10³" for exponent 3; empty for 0.
  std::string multiplier() const;
};

/// Ticks on [lo, hi] with a 1-2-5 step: of the steps giving between minCount and maxCount ticks
/// inside the range, the one whose count is nearest the middle of that interval (the coarser on
/// a tie); when none does (e.g. [2, 18.5]: step 2 gives 9, step 5 gives 3), the count nearest
/// the interval (the finer on a tie). A degenerate range gets one tick.
Ticks niceTicks(double lo, double hi, int minCount = 4, int maxCount = 8);
/// Ticks at every multiple of `step` inside [lo, hi], labelled.
Ticks ticksWithStep(double lo, double hi, double step);
/// The 1-2-5 steps that put between 1 and maxCount ticks on [lo, hi], fine to coarse: layout code
/// tries them in order until the labels fit.
std::vector<double> candidateSteps(double lo, double hi, int maxCount);

/// Ticks of a logarithmic axis on [lo, hi], both > 0: every `decades`-th power of ten inside,
/// labelled "10⁻⁴" (the powers whose exponent is a multiple of `decades`), and the other
/// 2–9 × 10^k as minor ticks. A range holding fewer than two powers of ten is labelled at
/// 1, 2 and 5 × 10^k instead ("2×10⁻⁴"), or at every 1–9 × 10^k if that still gives fewer
/// than two. Not positive or not finite: no ticks.
Ticks logTicks(double lo, double hi, int decades = 1);

/// A tick value written with the decimals its spacing needs (step 0.2 → one decimal), U+2212 as
/// the minus sign and no negative zero.
std::string formatTick(double value, double step);
/// "×10" with a superscript exponent, e.g. "×10⁻³".
std::string powerOfTen(int exponent);
/// "10" with a superscript exponent, e.g. "10⁻⁴": a tick label of a logarithmic axis.
std::string decadeLabel(int exponent);

}  // namespace granular::render
