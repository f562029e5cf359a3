/// The σ33 shape in words (paper_convexity.hpp).
#include "paper_convexity.hpp"

#include <cmath>

#include "run_header.hpp"

namespace granular::app {

std::string sigma33ShapeWords(double convexity) {
  if (!std::isfinite(convexity)) return "not defined (no stress at the walls)";
  // Classified by the digits the reader sees, so that "0 %" is never called convex.
  const std::string shown = format("%.0f", 100 * std::abs(convexity));
  if (shown == "0") return "the same at the centre as at the walls to within 0.5 % (flat)";
  return shown + " % " +
         (convexity > 0 ? "larger at the centre than at the walls (convex, peaked at the centre)"
                        : "smaller at the centre than at the walls (concave, lowest at the "
                          "centre)");
}

}  // namespace granular::app
