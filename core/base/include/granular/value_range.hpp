#pragma once
/// An allowed interval of a number: what a scene key, a material parameter or a command-line
/// value may take, and how a message says so ("must be in [0, 10]", "must be > 0").
#include <limits>
#include <string>

namespace granular {

struct ValueRange {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool loInclusive = true;
  bool hiInclusive = true;

  static constexpr ValueRange any() { return {}; }
  static constexpr ValueRange atLeast(double lo) { return {lo, kInf, true, true}; }  ///< [lo, ∞)
  static constexpr ValueRange above(double lo) { return {lo, kInf, false, true}; }   ///< (lo, ∞)
  static constexpr ValueRange closed(double lo, double hi) {                         ///< [lo, hi]
    return {lo, hi, true, true};
  }
  static constexpr ValueRange halfOpen(double lo, double hi) {  ///< [lo, hi)
    return {lo, hi, true, false};
  }
  static constexpr ValueRange aboveUpTo(double lo, double hi) {  ///< (lo, hi]
    return {lo, hi, false, true};
  }

  constexpr bool contains(double x) const {
    const bool aboveLo = loInclusive ? x >= lo : x > lo;
    const bool belowHi = hiInclusive ? x <= hi : x < hi;
    return aboveLo && belowHi;
  }
  /// "must be > 0", "must be in [0, 0.5)", ...
  std::string describe() const;
  /// The interval as docs/scenes.md writes it: "> 0", "[0, 0.5)", ">= 0".
  std::string bounds() const;

 private:
  static constexpr double kInf = std::numeric_limits<double>::infinity();
};

}  // namespace granular
