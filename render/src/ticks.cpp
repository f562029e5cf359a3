/// Nice ticks and their labels (ticks.hpp).
#include "granular/render/ticks.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace granular::render {

namespace {

/// A step m · 10^k with m ∈ {1, 2, 5}; values are computed as i·m / 10^−k for negative k, which
/// rounds to the nearest double of the decimal value (3 · 0.1 would give 0.30000000000000004).
struct Step {
  int mantissa;
  int power;
  double value() const {
    return power >= 0 ? mantissa * std::pow(10.0, power) : mantissa / std::pow(10.0, -power);
  }
  double at(long long i) const {
    return power >= 0 ? double(i * mantissa) * std::pow(10.0, power)
                      : double(i * mantissa) / std::pow(10.0, -power);
  }
};

struct Count {
  long long first = 0, last = -1;
  long long n() const { return last - first + 1; }
};

Count countFor(double lo, double hi, const Step& s) {
  const double step = s.value();
  const double eps = 1e-9 * (hi - lo);  // a tick a hair outside the range still counts
  Count c;
  c.first = (long long)std::ceil((lo - eps) / step);
  c.last = (long long)std::floor((hi + eps) / step);
  return c;
}

/// Every 1-2-5 step from one giving far too many ticks to one giving a single tick.
std::vector<Step> stepsFor(double lo, double hi) {
  std::vector<Step> steps;
  const int top = int(std::floor(std::log10(hi - lo)));
  for (int k = top - 3; k <= top + 1; ++k) {
    for (int m : {1, 2, 5}) steps.push_back({m, k});
  }
  return steps;
}

Ticks makeTicks(double lo, double hi, const Step& s) {
  Ticks t;
  t.step = s.value();
  const Count c = countFor(lo, hi, s);
  double maxAbs = 0.0;
  for (long long i = c.first; i <= c.last; ++i) {
    const double v = s.at(i);
    t.values.push_back(v);
    maxAbs = std::max(maxAbs, std::abs(v));
  }
  // Large or tiny numbers: a power of ten, a multiple of 3 (SI prefixes), comes out of the labels.
  if (maxAbs >= 1e5 || (maxAbs > 0.0 && maxAbs < 1e-3)) {
    t.exponent = 3 * int(std::floor(std::log10(maxAbs) / 3.0));
  }
  const double scale = std::pow(10.0, -t.exponent);
  for (double v : t.values) t.labels.push_back(formatTick(v * scale, t.step * scale));
  return t;
}

}  // namespace

std::vector<double> candidateSteps(double lo, double hi, int maxCount) {
  std::vector<double> out;
  if (lo > hi) std::swap(lo, hi);
  if (!(std::isfinite(lo) && std::isfinite(hi)) || !(hi - lo > 0.0)) return out;
  for (const Step& s : stepsFor(lo, hi)) {
    const long long n = countFor(lo, hi, s).n();
    if (n >= 1 && n <= maxCount) out.push_back(s.value());
  }
  return out;
}

Ticks niceTicks(double lo, double hi, int minCount, int maxCount) {
  if (lo > hi) std::swap(lo, hi);
  if (!(std::isfinite(lo) && std::isfinite(hi))) return {};
  if (!(hi - lo > 1e-12 * std::max(1.0, std::abs(lo)))) {
    Ticks t;
    t.values = {lo};
    t.step = std::abs(lo) > 0.0 ? std::pow(10.0, std::floor(std::log10(std::abs(lo)))) : 1.0;
    t.labels = {formatTick(lo, t.step)};
    return t;
  }
  minCount = std::max(1, minCount);
  maxCount = std::max(minCount, maxCount);
  const double middle = 0.5 * (minCount + maxCount);
  const Step* best = nullptr;
  double bestScore = 1e300;
  const std::vector<Step> steps = stepsFor(lo, hi);
  for (const Step& s : steps) {
    const long long n = countFor(lo, hi, s).n();
    // Inside the interval: distance to its middle; outside: 1000 + distance to the interval.
    const double score = (n >= minCount && n <= maxCount)
                             ? std::abs(double(n) - middle)
                             : 1000.0 + double(n < minCount ? minCount - n : n - maxCount);
    // Steps run fine to coarse: on a tie inside the interval the coarser step wins (cleaner),
    // outside it the finer one (with 3 or 9 ticks possible, 9 says more).
    if (score < bestScore || (score == bestScore && score < 1000.0)) {
      bestScore = score;
      best = &s;
    }
  }
  return makeTicks(lo, hi, *best);
}

Ticks ticksWithStep(double lo, double hi, double step) {
  if (lo > hi) std::swap(lo, hi);
  if (!(step > 0.0) || !(std::isfinite(lo) && std::isfinite(hi))) return {};
  // Express the step as m · 10^k when it is a 1-2-5 step, so values stay noise-free.
  const int k = int(std::floor(std::log10(step) + 1e-9));
  const double m = step / std::pow(10.0, k);
  for (int mm : {1, 2, 5, 10}) {
    if (std::abs(m - mm) < 1e-9 * mm)
      return makeTicks(lo, hi, Step{mm == 10 ? 1 : mm, mm == 10 ? k + 1 : k});
  }
  Ticks t;
  t.step = step;
  for (double v = std::ceil(lo / step - 1e-9) * step; v <= hi + 1e-9 * step; v += step) {
    t.values.push_back(v);
    t.labels.push_back(formatTick(v, step));
  }
  return t;
}

std::string formatTick(double value, double step) {
  step = std::abs(step);
  int decimals = 0;
  // The fewest decimals that write the step exactly (0.25 needs two, 0.2 one, 20 none).
  if (step > 0.0 && std::isfinite(step)) {
    while (decimals < 12) {
      const double scaled = step * std::pow(10.0, decimals);
      if (std::abs(scaled - std::round(scaled)) < 1e-6 * std::max(1.0, scaled)) break;
      ++decimals;
    }
  }
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
  std::string s = buffer;
  const bool negative = !s.empty() && s[0] == '-';
  if (negative) {
    s.erase(0, 1);
    const bool zero = s.find_first_not_of("0.") == std::string::npos;
    if (!zero) s.insert(0, "\u2212");
  }
  return s;
}

std::string powerOfTen(int exponent) {
  return "\u00d7" + decadeLabel(exponent);
}

std::string decadeLabel(int exponent) {
  static const char* const kDigits[10] = {"\u2070", "\u00b9", "\u00b2", "\u00b3", "\u2074",
                                          "\u2075", "\u2076", "\u2077", "\u2078", "\u2079"};
  std::string s = "10";
  if (exponent < 0) s += "\u207b";
  const std::string digits = std::to_string(std::abs(exponent));
  for (char c : digits) s += kDigits[c - '0'];
  return s;
}

Ticks logTicks(double lo, double hi, int decades) {
  if (lo > hi) std::swap(lo, hi);
  if (!(lo > 0.0 && std::isfinite(hi))) return {};
  decades = std::max(1, decades);
  const double eps = 1e-9;  // a tick a hair outside the range still counts (in log10 units)
  const int first = int(std::floor(std::log10(lo) - eps));
  const int last = int(std::ceil(std::log10(hi) + eps));
  auto inside = [&](double v) {
    return std::log10(v) >= std::log10(lo) - eps && std::log10(v) <= std::log10(hi) + eps;
  };
  // m · 10^k, computed as m / 10^−k for negative k: the double nearest the decimal value.
  auto value = [](int m, int k) { return k >= 0 ? m * std::pow(10.0, k) : m / std::pow(10.0, -k); };
  auto label = [](int m, int k) {
    return m == 1 ? decadeLabel(k) : std::to_string(m) + "\u00d7" + decadeLabel(k);
  };
  int powers = 0;
  for (int k = first; k <= last; ++k) powers += inside(value(1, k)) ? 1 : 0;
  // Which mantissas are labelled: the powers alone, or more of them on a short range.
  std::vector<int> labelled = {1};
  if (powers < 2) {
    labelled = {1, 2, 5};
    int count = 0;
    for (int k = first; k <= last; ++k) {
      for (int m : labelled) count += inside(value(m, k)) ? 1 : 0;
    }
    if (count < 2) labelled = {1, 2, 3, 4, 5, 6, 7, 8, 9};
  }
  Ticks t;
  for (int k = first; k <= last; ++k) {
    for (int m = 1; m <= 9; ++m) {
      const double v = value(m, k);
      if (!inside(v)) continue;
      const bool major = std::find(labelled.begin(), labelled.end(), m) != labelled.end() &&
                         (powers < 2 || k % decades == 0);
      if (major) {
        t.values.push_back(v);
        t.labels.push_back(label(m, k));
      } else {
        t.minor.push_back(v);
      }
    }
  }
  t.step = powers < 2 ? 0.0 : double(decades);  // in decades
  return t;
}

std::string Ticks::multiplier() const {
  return exponent == 0 ? std::string() : powerOfTen(exponent);
}

}  // namespace granular::render
