#pragma once
/// A robust minimum of a function of one variable on a closed interval, for the fits of
/// janssen.hpp: a grid finds the basin (so a function with several local minima gives the
/// deepest one the grid sees), golden-section search then narrows it without derivatives.
#include <functional>

namespace granular {

/// Where the minimum lies and what it is.
struct ScalarMinimum {
  double x = 0;          ///< the argument of the smallest value found [the argument's unit]
  double value = 0;      ///< f(x) [f's unit]
  bool atBound = false;  ///< x lies within the tolerance of lo or hi: the minimum may be outside
};

/// The minimum of f over [lo, hi]: f at `gridPoints` (>= 3) evenly spaced points, then
/// golden-section search between the neighbours of the smallest until the bracket is narrower
/// than `tolerance` [the argument's unit]. Non-finite values of f count as larger than any
/// finite one. Throws std::invalid_argument when lo >= hi, gridPoints < 3 or tolerance <= 0.
ScalarMinimum minimiseOnInterval(const std::function<double(double)>& f, double lo, double hi,
                                 int gridPoints, double tolerance);

}  // namespace granular
