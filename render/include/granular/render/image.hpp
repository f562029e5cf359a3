#pragma once
/// An RGBA image, the currency of the renderer: GL views are read back into one, the 2-D canvas
/// draws into one, PNG files are written from one.
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <vector>

namespace granular::render {

/// 8-bit RGBA colour.
struct Rgba {
  std::uint8_t r = 0, g = 0, b = 0, a = 255;
  bool operator==(const Rgba&) const = default;
};

/// Row-major, top row first, 4 bytes per pixel (RGBA), non-premultiplied.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;  ///< width·height·4 bytes

  Image() = default;
  Image(int w, int h, Rgba fill = {255, 255, 255, 255});
  Rgba at(int x, int y) const;
  void set(int x, int y, Rgba c);
  bool empty() const { return width == 0 || height == 0; }
};

/// A file that cannot be written or read, or is not a PNG.
class ImageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Writes a PNG (8-bit RGBA, low compression: encoding costs more than drawing). Written to a
/// temporary file and renamed, so a reader never sees half an image; a failed write throws
/// granular::IoError naming the file and the reason, and keeps the previous file. `dpi` goes into
/// the pHYs chunk so that publishers' tools size the figure right. `compressionLevel` 0-9 (9 for
/// files kept in the repository, like golden images).
void writePng(const Image& image, const std::filesystem::path& file, double dpi = 150.0,
              int compressionLevel = 1);
/// Reads an 8-bit RGB or RGBA PNG (as written by writePng).
Image readPng(const std::filesystem::path& file);

/// Per-pixel comparison for image-diff tests.
struct ImageDiff {
  bool sameSize = false;
  long differing = 0;       ///< pixels with some channel differing by more than the tolerance
  double fraction = 0.0;    ///< differing / pixel count
  int maxChannelDelta = 0;  ///< largest channel difference seen
  Image diff;               ///< differing pixels red on a faded copy of `expected`
};
ImageDiff compareImages(const Image& actual, const Image& expected, int channelTolerance);

}  // namespace granular::render
