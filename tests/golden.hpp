#pragma once
/// Image-diff testing against golden PNGs in assets/golden/ (docs/architecture.md §3): per-channel
/// tolerance and a maximum fraction of differing pixels. On failure the actual image and a diff
/// image are written next to the build (build/.../golden-failures/) and the message says where.
///
/// Regenerating goldens is a deliberate act: run the tests with GRANULAR_UPDATE_GOLDEN=1 set,
/// look at every changed PNG, and commit them with a reason. Without it a missing golden fails.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "granular/render/image.hpp"

namespace granular::testing {

inline constexpr int kGoldenChannelTolerance = 5;            ///< per channel, of 255
inline constexpr double kGoldenMaxDifferingFraction = 1e-3;  ///< 0.1 % of the pixels

inline std::filesystem::path goldenPath(const std::string& name) {
  return std::filesystem::path(GRANULAR_SOURCE_DIR) / "assets" / "golden" / (name + ".png");
}

inline std::filesystem::path goldenFailureDir() {
  return std::filesystem::path(GRANULAR_BINARY_DIR) / "golden-failures";
}

/// Compares `actual` with the golden image `name`; regenerates it when GRANULAR_UPDATE_GOLDEN=1.
inline ::testing::AssertionResult matchesGolden(const render::Image& actual,
                                                const std::string& name) {
  const std::filesystem::path golden = goldenPath(name);
  const char* update = std::getenv("GRANULAR_UPDATE_GOLDEN");
  if (update && std::string(update) == "1") {
    render::writePng(actual, golden, 100.0, 9);
    return ::testing::AssertionSuccess() << "regenerated " << golden.string();
  }
  if (!std::filesystem::exists(golden)) {
    return ::testing::AssertionFailure()
           << "no golden image " << golden.string()
           << " (create it on purpose with GRANULAR_UPDATE_GOLDEN=1 and look at it)";
  }
  const render::Image expected = render::readPng(golden);
  const render::ImageDiff d = render::compareImages(actual, expected, kGoldenChannelTolerance);
  if (d.sameSize && d.fraction <= kGoldenMaxDifferingFraction) {
    return ::testing::AssertionSuccess();
  }
  std::filesystem::create_directories(goldenFailureDir());
  const auto actualPath = goldenFailureDir() / (name + ".actual.png");
  const auto diffPath = goldenFailureDir() / (name + ".diff.png");
  render::writePng(actual, actualPath, 100.0);
  if (d.sameSize) render::writePng(d.diff, diffPath, 100.0);
  auto failure = ::testing::AssertionFailure();
  if (!d.sameSize) {
    failure << name << ": size " << actual.width << "x" << actual.height << ", golden "
            << expected.width << "x" << expected.height;
  } else {
    failure << name << ": " << d.differing << " pixels (" << 100.0 * d.fraction
            << " %) differ by more than " << kGoldenChannelTolerance << "/255 (max "
            << d.maxChannelDelta << "); allowed " << 100.0 * kGoldenMaxDifferingFraction
            << " %. Diff: " << diffPath.string();
  }
  return failure << "; actual: " << actualPath.string();
}

}  // namespace granular::testing
