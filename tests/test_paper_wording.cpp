/// The words report.md puts beside its numbers agree with them: the σ33 shape at mid-depth is
/// convex, flat or concave as the printed percentage says.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "paper_convexity.hpp"

using granular::app::sigma33ShapeWords;

namespace {

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

// A difference printed as 0 % is flat, whatever its sign below the rounding; from the first
// whole per cent on it is convex (centre larger) or concave (centre smaller).
TEST(PaperWording, Sigma33ShapeFollowsThePrintedPercentage) {
  for (double flat : {0.0, 0.004, -0.004, 0.0049, -0.0049}) {
    const std::string words = sigma33ShapeWords(flat);
    EXPECT_TRUE(contains(words, "(flat)")) << flat << ": " << words;
    EXPECT_FALSE(contains(words, "convex")) << flat << ": " << words;
    EXPECT_FALSE(contains(words, "concave")) << flat << ": " << words;
    EXPECT_FALSE(contains(words, "larger")) << flat << ": " << words;
    EXPECT_FALSE(contains(words, "smaller")) << flat << ": " << words;
  }
  for (double convex : {0.0051, 0.006, 0.04, 0.3}) {
    const std::string words = sigma33ShapeWords(convex);
    const std::string percent = std::to_string(std::lround(100 * convex)) + " % larger";
    EXPECT_EQ(words.rfind(percent, 0), 0u) << convex << ": " << words;
    EXPECT_TRUE(contains(words, "(convex, peaked at the centre)")) << convex << ": " << words;
  }
  for (double concave : {-0.0051, -0.006, -0.04, -0.3}) {
    const std::string words = sigma33ShapeWords(concave);
    const std::string percent = std::to_string(std::lround(-100 * concave)) + " % smaller";
    EXPECT_EQ(words.rfind(percent, 0), 0u) << concave << ": " << words;
    EXPECT_TRUE(contains(words, "(concave")) << concave << ": " << words;
    EXPECT_FALSE(contains(words, "convex")) << concave << ": " << words;
  }
  EXPECT_FALSE(contains(sigma33ShapeWords(std::nan("")), "convex"));
}
