#include "granular/value_range.hpp"

#include <cmath>

#include "number_format.hpp"

namespace granular {

std::string ValueRange::bounds() const {
  const bool hasLo = std::isfinite(lo);
  const bool hasHi = std::isfinite(hi);
  if (hasLo && hasHi) {
    return std::string(loInclusive ? "[" : "(") + formatNumber(lo) + ", " + formatNumber(hi) +
           (hiInclusive ? "]" : ")");
  }
  if (hasLo) return std::string(loInclusive ? ">= " : "> ") + formatNumber(lo);
  if (hasHi) return std::string(hiInclusive ? "<= " : "< ") + formatNumber(hi);
  return "finite";
}

std::string ValueRange::describe() const {
  const bool hasLo = std::isfinite(lo);
  const bool hasHi = std::isfinite(hi);
  if (hasLo && hasHi) return "must be in " + bounds();
  if (hasLo || hasHi) return "must be " + bounds();
  return "must be a finite number";
}

}  // namespace granular
