/// Grid and golden-section minimum of a function of one variable (scalar_minimum.hpp).
#include "scalar_minimum.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace granular {
namespace {

/// f(x), with NaN and ±inf mapped to +inf so that comparisons order them last.
double finiteOrHuge(const std::function<double(double)>& f, double x) {
  const double v = f(x);
  return std::isfinite(v) ? v : std::numeric_limits<double>::infinity();
}

}  // namespace

ScalarMinimum minimiseOnInterval(const std::function<double(double)>& f, double lo, double hi,
                                 int gridPoints, double tolerance) {
  if (!(lo < hi) || gridPoints < 3 || !(tolerance > 0)) {
    throw std::invalid_argument(
        "minimiseOnInterval: needs lo < hi, >= 3 grid points and a "
        "positive tolerance");
  }
  const double step = (hi - lo) / (gridPoints - 1);
  int best = 0;
  double bestValue = std::numeric_limits<double>::infinity();
  for (int k = 0; k < gridPoints; ++k) {
    const double v = finiteOrHuge(f, lo + k * step);
    if (v < bestValue) {
      bestValue = v;
      best = k;
    }
  }
  ScalarMinimum result{lo + best * step, bestValue, false};

  // The minimum of a function unimodal near the best grid point lies between its neighbours.
  double a = lo + (best > 0 ? best - 1 : 0) * step;
  double b = lo + (best < gridPoints - 1 ? best + 1 : gridPoints - 1) * step;
  const double invPhi = (std::sqrt(5.0) - 1.0) / 2.0;
  double c = b - invPhi * (b - a);
  double d = a + invPhi * (b - a);
  double fc = finiteOrHuge(f, c);
  double fd = finiteOrHuge(f, d);
  // Each pass shrinks the bracket by 0.618; 200 passes reach any tolerance above 1e-40 of it.
  for (int pass = 0; pass < 200 && b - a > tolerance; ++pass) {
    if (fc < fd) {
      b = d;
      d = c;
      fd = fc;
      c = b - invPhi * (b - a);
      fc = finiteOrHuge(f, c);
    } else {
      a = c;
      c = d;
      fc = fd;
      d = a + invPhi * (b - a);
      fd = finiteOrHuge(f, d);
    }
  }
  if (fc < result.value) result = {c, fc, false};
  if (fd < result.value) result = {d, fd, false};
  result.atBound = result.x - lo <= 2 * tolerance || hi - result.x <= 2 * tolerance;
  return result;
}

}  // namespace granular
