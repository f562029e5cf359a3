#pragma once
/// A 2-D canvas over an Image: anti-aliased lines, polygons, circles, arrows, text and images, in
/// pixel coordinates (origin top-left, y down, doubles for sub-pixel positions; geometry.hpp).
///
/// Lines are drawn by coverage: each pixel takes min(1, w/2 + 1/2 − distance to the centre line)
/// (a one-pixel box filter across the edge), and the pieces of a path combine by maximum, so a
/// polyline's overlapping joints are not drawn twice. A horizontal line of width w ≥ 1 therefore
/// deposits exactly w pixels of ink per column. Lines thinner than a pixel are drawn one pixel
/// wide at proportionally lower opacity. Filled shapes are scan-converted with 16 sub-scanlines
/// per pixel row and exact horizontal coverage, under the non-zero or even-odd rule. Colours
/// blend "over" in sRGB space like Matplotlib's Agg backend, so figures look the same.
#include <span>
#include <string_view>
#include <vector>

#include "granular/render/font.hpp"
#include "granular/render/geometry.hpp"
#include "granular/render/image.hpp"

namespace granular::render {

enum class LineCap { Butt, Round, Square };
enum class FillRule { NonZero, EvenOdd };
enum class HAlign { Left, Center, Right };
/// Vertical text alignment: Top and Bottom are the font's ascender and descender (the same for
/// every string, so labels in a row line up); Middle is half the cap height above the baseline,
/// which centres digits and capitals on the anchor.
enum class VAlign { Top, Middle, Baseline, Bottom };
enum class Filter { Nearest, Bilinear, Box };

/// How a line is drawn. Joins are always round.
struct Stroke {
  Rgba color{0, 0, 0, 255};
  double width = 1.0;        ///< [px]
  std::vector<double> dash;  ///< alternating on/off lengths [px]; empty = solid
  double dashOffset = 0.0;   ///< start into the pattern [px]
  LineCap cap = LineCap::Butt;
};

/// Matplotlib's dash patterns for a line of the given width [px]: lengths grow with the width
/// so thick dashed lines keep their rhythm.
std::vector<double> dashedPattern(double width);
std::vector<double> dottedPattern(double width);

struct TextStyle {
  double size = 13.9;  ///< em size [px] (10 pt at 100 dpi)
  FontWeight weight = FontWeight::Regular;
  Rgba color{0, 0, 0, 255};
  HAlign hAlign = HAlign::Left;
  VAlign vAlign = VAlign::Baseline;
  /// Counter-clockwise rotation [degrees]. 0 and ±90 use hinted glyph bitmaps (crisp); other
  /// angles fill unhinted outlines.
  double angle = 0.0;
};

/// An arrow glyph: a shaft and a triangular head, drawn as one filled polygon.
struct ArrowStyle {
  Rgba color{0, 0, 0, 255};
  double shaftWidth = 1.5;  ///< [px]
  double headLength = 0.0;  ///< [px]; 0 = 4.5 shaft widths (at least 5 px)
  double headWidth = 0.0;   ///< full width of the head [px]; 0 = 3.5 shaft widths (at least 4 px)
};

class Canvas {
 public:
  Canvas(int width, int height, Rgba background = {255, 255, 255, 255});
  explicit Canvas(Image image);

  int width() const { return image_.width; }
  int height() const { return image_.height; }
  const Image& image() const { return image_; }
  Image& image() { return image_; }
  /// Moves the image out; the canvas is left empty.
  Image takeImage();

  // --- Clipping: drawing is limited to the intersection of the pushed rectangles, rounded to
  // whole pixels (a pixel is inside when its centre is).
  void pushClip(Rect r);
  void popClip();
  Rect clip() const;

  // --- Lines
  void line(Point a, Point b, const Stroke& stroke);
  void polyline(std::span<const Point> points, const Stroke& stroke);
  /// Several polylines drawn as one path: where they overlap, ink is not doubled.
  void polylines(std::span<const std::vector<Point>> lines, const Stroke& stroke);
  /// Closed outline through the points.
  void strokePolygon(std::span<const Point> points, const Stroke& stroke);
  void strokeRect(Rect r, const Stroke& stroke);
  void strokeCircle(Point center, double radius, const Stroke& stroke);

  // --- Fills
  void fillPolygon(std::span<const Point> points, Rgba color, FillRule rule = FillRule::NonZero);
  /// Several closed contours as one shape (holes by the rule: even-odd, or opposite winding).
  void fillPath(std::span<const std::vector<Point>> contours, Rgba color,
                FillRule rule = FillRule::NonZero);
  void fillRect(Rect r, Rgba color);
  void fillCircle(Point center, double radius, Rgba color);
  /// Arrow from tail to tip; a shaft shorter than the head shrinks the head with it.
  void arrow(Point tail, Point tip, const ArrowStyle& style);

  // --- Text (UTF-8)
  TextMetrics measureText(std::string_view text, const TextStyle& style) const;
  /// Axis-aligned box the text would occupy: advance width × (ascent + descent), rotated.
  Rect textBounds(Point anchor, std::string_view text, const TextStyle& style) const;
  /// Draws text aligned on the anchor; returns textBounds().
  Rect text(Point anchor, std::string_view text, const TextStyle& style);

  // --- Images (source-over with the source's alpha)
  /// Unscaled, top-left corner at a whole pixel (the position is rounded).
  void blit(const Image& source, Point topLeft);
  /// Scaled into the rectangle (edges rounded to whole pixels). Box averages every source pixel
  /// under a destination pixel (for shrinking); Bilinear interpolates (for enlarging).
  void blit(const Image& source, Rect destination, Filter filter = Filter::Bilinear);

 private:
  struct PixelBox {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // half-open
  };
  PixelBox clipBox() const;
  void ensureMask();
  /// Strokes open polylines (round joins, `cap` at the ends) into the coverage mask.
  void strokeIntoMask(std::span<const std::vector<Point>> pieces, double halfWidth, LineCap cap);
  void segmentIntoMask(Point a, Point b, double halfWidth, LineCap capA, LineCap capB,
                       const PixelBox& box);
  void ringIntoMask(Point center, double radius, double halfWidth, bool filled);
  void markMask(int x, int y, float coverage);
  /// Blends the coverage mask in `color` scaled by `opacity`, then clears it.
  void flushMask(Rgba color, double opacity);
  void strokePaths(std::span<const std::vector<Point>> lines, bool closed, const Stroke& stroke);

  Image image_;
  std::vector<PixelBox> clips_;
  std::vector<float> mask_;             ///< stroke coverage, width·height, zero between uses
  std::vector<int> dirtyX0_, dirtyX1_;  ///< per row: touched columns [x0, x1)
  int dirtyY0_ = 0, dirtyY1_ = 0;       ///< touched rows [y0, y1)
};

}  // namespace granular::render
