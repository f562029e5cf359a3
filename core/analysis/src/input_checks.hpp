#pragma once
/// The checks the silo analyses (janssen.hpp, beverloo.hpp, discharge_rate.hpp, wall_bands.hpp,
/// slice_stress.hpp, lateral_ratio.hpp) make of their inputs: each refusal is a
/// std::invalid_argument that names the function, the value at fault and, in a series, its index,
/// so that a caller fitting measured data learns which sample is bad.
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

#include "number_format.hpp"

namespace granular::input_checks {

/// Throws unless `value` is finite; `what` names it ("fitJanssen: hydraulic radius").
inline void requireFinite(double value, const std::string& what) {
  if (!std::isfinite(value)) {
    throw std::invalid_argument(what + " must be finite (got " + formatNumber(value) + ")");
  }
}

/// Throws unless `value` is finite and > 0.
inline void requirePositive(double value, const std::string& what) {
  requireFinite(value, what);
  if (value <= 0) {
    throw std::invalid_argument(what + " must be > 0 (got " + formatNumber(value) + ")");
  }
}

/// Throws unless `value` is finite and >= 0.
inline void requireNonNegative(double value, const std::string& what) {
  requireFinite(value, what);
  if (value < 0) {
    throw std::invalid_argument(what + " must be >= 0 (got " + formatNumber(value) + ")");
  }
}

/// Throws unless every element is finite, naming the first that is not by its index.
inline void requireFiniteSeries(const std::vector<double>& values, const std::string& what) {
  for (std::size_t k = 0; k < values.size(); ++k) {
    requireFinite(values[k], what + "[" + std::to_string(k) + "]");
  }
}

/// Throws unless the two series have the same length.
inline void requireSameLength(const std::vector<double>& a, const std::vector<double>& b,
                              const std::string& what) {
  if (a.size() != b.size()) {
    throw std::invalid_argument(what + ": " + std::to_string(a.size()) + " against " +
                                std::to_string(b.size()) + " values");
  }
}

/// Throws unless the series has at least `minimum` values; `why` says what needs them.
inline void requireAtLeast(std::size_t count, std::size_t minimum, const std::string& what,
                           const std::string& why) {
  if (count < minimum) {
    throw std::invalid_argument(what + ": " + std::to_string(count) + " points, at least " +
                                std::to_string(minimum) + " needed (" + why + ")");
  }
}

/// Throws unless the edges are finite and strictly ascending, with at least one band.
inline void requireAscendingEdges(const std::vector<double>& edges, const std::string& what) {
  requireFiniteSeries(edges, what);
  if (edges.size() < 2) {
    throw std::invalid_argument(what + ": " + std::to_string(edges.size()) +
                                " edges, at least 2 needed (one band)");
  }
  for (std::size_t k = 1; k < edges.size(); ++k) {
    if (!(edges[k] > edges[k - 1])) {
      throw std::invalid_argument(what + " must be strictly ascending: [" + std::to_string(k - 1) +
                                  "] = " + formatNumber(edges[k - 1]) + ", [" + std::to_string(k) +
                                  "] = " + formatNumber(edges[k]));
    }
  }
}

}  // namespace granular::input_checks
