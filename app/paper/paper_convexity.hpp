#pragma once
/// How report.md words the shape of σ33 across the bed at mid-depth (the paper's Fig. 9):
/// convex, flat or concave, always agreeing with the percentage it prints beside the word.
#include <string>

namespace granular::app {

/// `convexity` = |σ33| at the centre / |σ33| at the walls − 1 at mid-depth [-]. The words follow
/// the difference as printed, in whole per cent: "4 % larger at the centre than at the walls
/// (convex, peaked at the centre)", "4 % smaller … (concave, lowest at the centre)", and, where
/// the printed difference is 0 %, "the same at the centre as at the walls to within 0.5 %
/// (flat)".
std::string sigma33ShapeWords(double convexity);

}  // namespace granular::app
