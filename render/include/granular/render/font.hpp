#pragma once
/// Text with FreeType and DejaVu Sans (Debian package fonts-dejavu-core): UTF-8 strings (labels
/// carry σ, μ, ‰, ², ³, ·, −), kerning, metrics for layout, glyph coverage for drawing. Drawing
/// into an image is Canvas's job (canvas.hpp); this file turns strings into coverage and outlines.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "granular/render/geometry.hpp"

namespace granular::render {

enum class FontWeight { Regular, Bold };

/// A missing or unreadable font file; the message names the path.
class FontError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Horizontal layout of one line of text at one size.
struct TextMetrics {
  double width = 0.0;      ///< pen advance including kerning [px]
  double ascent = 0.0;     ///< font ascender above the baseline, same for every string [px]
  double descent = 0.0;    ///< font descender below the baseline, positive [px]
  double capHeight = 0.0;  ///< height of capitals and digits above the baseline [px]
};

/// One line of text rasterised horizontally: 8-bit coverage, row-major, top row first.
struct TextRaster {
  int width = 0;
  int height = 0;
  int originX = 0;    ///< column of the pen's start (x = 0 of the string) [px]
  int baselineY = 0;  ///< row of the baseline (the row just below it holds descenders) [px]
  std::vector<std::uint8_t> coverage;  ///< width·height, 0 = empty, 255 = covered
};

/// Decodes UTF-8; malformed bytes become U+FFFD so that a bad label still shows where it is bad.
std::u32string decodeUtf8(std::string_view utf8);

/// DejaVu Sans at one pixel size with its glyph cache. Thread-safe; shared through get().
class Font {
 public:
  /// The font of a weight at an em size [px], loaded on first use and cached per (weight, size).
  /// Throws FontError naming the file when it is missing or unreadable.
  static std::shared_ptr<const Font> get(FontWeight weight, double pixelSize);
  /// The file a weight is read from (under GRANULAR_FONT_DIR).
  static std::filesystem::path file(FontWeight weight);
  /// A font file at an em size [px], uncached. Throws FontError naming the file when it is
  /// missing or unreadable.
  static std::shared_ptr<const Font> fromFile(const std::filesystem::path& file, double pixelSize);

  ~Font();
  Font(const Font&) = delete;
  Font& operator=(const Font&) = delete;

  double pixelSize() const;  ///< em size [px]
  /// Width with kerning and the font's vertical metrics [px].
  TextMetrics measure(std::string_view utf8) const;
  /// Coverage of the string with the pen starting `subpixelX` ∈ [0, 1) px right of column
  /// originX (glyphs are cached at quarter-pixel phases, so spacing stays even).
  TextRaster rasterize(std::string_view utf8, double subpixelX = 0.0) const;
  /// Unhinted glyph outlines of the string as closed polygons (curves flattened to within
  /// ~0.1 px), pen starting at (0, 0) on the baseline, y down [px]. Filled with the non-zero
  /// rule they give the text at any angle.
  std::vector<std::vector<Point>> outline(std::string_view utf8) const;

 private:
  struct Impl;
  explicit Font(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace granular::render
