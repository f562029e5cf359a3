#pragma once
/// "Did you mean ...?" for names a user typed: scene keys, enumeration values, CSV columns
/// (private to the core).
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace granular {

/// Optimal string alignment distance: Levenshtein plus adjacent transpositions, because
/// "frcition" is one slip of the fingers away from "friction", not two. Case-insensitive.
std::size_t editDistance(std::string_view a, std::string_view b);

/// The candidate nearest to `word` by edit distance, or empty if none is reasonably close.
std::string nearestName(std::string_view word, const std::vector<std::string_view>& candidates);

}  // namespace granular
