/// The 2-D canvas (render/canvas.hpp), its font and colour maps: coverage of lines and fills
/// against their exact areas, text against its measured width, UTF-8, clipping, blits.
///
/// Sections: helpers · lines · fills · text · images · colour maps · inspection.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "granular/render/canvas.hpp"
#include "granular/render/colormap.hpp"
#include "granular/render/font.hpp"
#include "granular/render/inspect.hpp"

namespace granular::render {
namespace {

// ---------------------------------------------------------------------------------------------
// Helpers

constexpr Rgba kWhite{255, 255, 255, 255};
constexpr Rgba kBlack{0, 0, 0, 255};

/// Ink of black drawn on white at a pixel: 0 (white) … 1 (black).
double ink(const Image& image, int x, int y) {
  return (255.0 - image.at(x, y).r) / 255.0;
}

double columnInk(const Image& image, int x) {
  double sum = 0.0;
  for (int y = 0; y < image.height; ++y) sum += ink(image, x, y);
  return sum;
}

double totalInk(const Image& image) {
  double sum = 0.0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) sum += ink(image, x, y);
  }
  return sum;
}

// 8-bit blending rounds each pixel by at most half a level.
constexpr double kRounding = 0.5 / 255.0;

// ---------------------------------------------------------------------------------------------
// Lines

TEST(Canvas, HorizontalLineDepositsItsWidthPerColumnWithSoftEdges) {
  for (double width : {1.0, 1.5, 2.0, 3.0, 4.5}) {
    Canvas canvas(60, 40);
    const double y = 20.3;  // off the pixel grid, so both edges are partial
    Stroke s;
    s.width = width;
    canvas.line({5.0, y}, {55.0, y}, s);
    const Image& img = canvas.image();
    // Coverage is a one-pixel box filter across the edge: a column holds exactly `width` of ink.
    EXPECT_NEAR(columnInk(img, 30), width, 40 * kRounding) << "width " << width;
    // Ink only within half a pixel of the stroke's edges.
    for (int row = 0; row < img.height; ++row) {
      const double distance = std::abs(row + 0.5 - y);
      if (distance >= 0.5 * width + 0.5) {
        EXPECT_EQ(ink(img, 30, row), 0.0) << row;
      }
      if (distance <= 0.5 * width - 0.5) {
        EXPECT_NEAR(ink(img, 30, row), 1.0, kRounding) << row;
      }
    }
    // Edges are anti-aliased: the rows at the stroke's edges are partly covered.
    int partial = 0;
    for (int row = 0; row < img.height; ++row) {
      const double c = ink(img, 30, row);
      partial += (c > 0.05 && c < 0.95) ? 1 : 0;
    }
    EXPECT_GE(partial, 1) << "width " << width;
    // Butt ends: columns 5 … 54 inked, nothing beyond (pixel centres x + 0.5 inside [5, 55]).
    const InkBox box = inkBounds(img, kWhite, 0);
    EXPECT_EQ(box.x0, 5);
    EXPECT_EQ(box.x1, 54);
  }
}

TEST(Canvas, DiagonalLineInkMatchesItsArea) {
  Canvas canvas(120, 120);
  Stroke s;
  s.width = 2.0;
  const Point a{10.2, 15.7}, b{100.9, 104.1};
  canvas.line(a, b, s);
  // A butt-capped stroke is a rectangle length × width.
  const double area = length(b - a) * s.width;
  EXPECT_NEAR(totalInk(canvas.image()), area, 0.02 * area);
}

TEST(Canvas, ThinLinesAreFainterNotNarrower) {
  Canvas canvas(40, 20);
  Stroke s;
  s.width = 0.4;
  canvas.line({2.0, 10.5}, {38.0, 10.5}, s);
  // One pixel wide at 40 % opacity: the same ink per length as an exact 0.4 px line.
  EXPECT_NEAR(columnInk(canvas.image(), 20), 0.4, 2 * kRounding);
  EXPECT_NEAR(ink(canvas.image(), 20, 10), 0.4, kRounding);
}

TEST(Canvas, PolylineJointsAreNotInkedTwice) {
  // Translucent strokes show double inking as darker spots where segments overlap.
  Canvas canvas(80, 40);
  Stroke s;
  s.width = 4.0;
  s.color = {0, 0, 0, 128};
  const Point pts[4] = {{5.0, 20.5}, {25.0, 20.5}, {45.0, 20.5}, {75.0, 20.5}};
  canvas.polyline(pts, s);
  const Image& img = canvas.image();
  const int middle = img.at(35, 20).r, joint = img.at(25, 20).r;
  EXPECT_EQ(middle, joint);
}

TEST(Canvas, DashedLineInkFollowsThePattern) {
  Canvas canvas(420, 20);
  Stroke s;
  s.width = 2.0;
  s.dash = dashedPattern(s.width);
  canvas.line({10.0, 10.0}, {410.0, 10.0}, s);
  const double on = s.dash[0], off = s.dash[1];
  const double length = 400.0;
  // Whole periods plus the drawn part of the last one.
  const double periods = std::floor(length / (on + off));
  const double expected = s.width * (periods * on + std::min(on, length - periods * (on + off)));
  EXPECT_NEAR(totalInk(canvas.image()), expected, 0.01 * expected);
  // Gaps really are empty: some column between the ends has no ink at all.
  int empty = 0;
  for (int x = 12; x < 408; ++x) empty += columnInk(canvas.image(), x) == 0.0 ? 1 : 0;
  EXPECT_GT(empty, 0);
}

TEST(Canvas, NanBreaksAPolyline) {
  Canvas canvas(100, 20);
  Stroke s;
  s.width = 2.0;
  const Point pts[4] = {{5.0, 10.0}, {40.0, 10.0}, {NAN, NAN}, {60.0, 10.0}};
  const Point tail[2] = {{60.0, 10.0}, {95.0, 10.0}};
  canvas.polyline(pts, s);
  canvas.polyline(tail, s);
  EXPECT_EQ(columnInk(canvas.image(), 50), 0.0);
  EXPECT_GT(columnInk(canvas.image(), 30), 1.9);
}

// ---------------------------------------------------------------------------------------------
// Fills

TEST(Canvas, FilledSquareOnThePixelGridIsExact) {
  Canvas canvas(40, 40);
  canvas.fillRect({10.0, 10.0, 20.0, 20.0}, kBlack);
  EXPECT_EQ(countColorPixels(canvas.image(), kBlack, 0), 400);
  const InkBox box = inkBounds(canvas.image(), kWhite, 0);
  EXPECT_EQ(box.inkPixels, 400);
  EXPECT_EQ(box.x0, 10);
  EXPECT_EQ(box.x1, 29);
}

TEST(Canvas, FilledSquareOffTheGridCoversItsAreaWithinOnePixelBorder) {
  Canvas canvas(40, 40);
  const Rect r{10.4, 9.7, 20.0, 20.0};
  canvas.fillRect(r, kBlack);
  EXPECT_NEAR(totalInk(canvas.image()), r.w * r.h, 0.5);
  const InkBox box = inkBounds(canvas.image(), kWhite, 0);
  EXPECT_EQ(box.x0, int(std::floor(r.left())));
  EXPECT_EQ(box.x1, int(std::ceil(r.right())) - 1);
  EXPECT_EQ(box.y0, int(std::floor(r.top())));
  EXPECT_EQ(box.y1, int(std::ceil(r.bottom())) - 1);
  // The interior, one pixel in from every edge, is solid.
  for (int y = int(std::ceil(r.top())); y < int(std::floor(r.bottom())); ++y) {
    for (int x = int(std::ceil(r.left())); x < int(std::floor(r.right())); ++x) {
      ASSERT_EQ(canvas.image().at(x, y), kBlack) << x << "," << y;
    }
  }
}

TEST(Canvas, FillRulesDifferOnAHole) {
  // Two squares wound the same way: non-zero fills the inner one, even-odd leaves a hole.
  const std::vector<std::vector<Point>> path = {{{5, 5}, {35, 5}, {35, 35}, {5, 35}},
                                                {{15, 15}, {25, 15}, {25, 25}, {15, 25}}};
  Canvas nonZero(40, 40), evenOdd(40, 40);
  nonZero.fillPath(path, kBlack, FillRule::NonZero);
  evenOdd.fillPath(path, kBlack, FillRule::EvenOdd);
  EXPECT_EQ(nonZero.image().at(20, 20), kBlack);
  EXPECT_EQ(evenOdd.image().at(20, 20), kWhite);
  EXPECT_EQ(countColorPixels(nonZero.image(), kBlack, 0), 30 * 30);
  EXPECT_EQ(countColorPixels(evenOdd.image(), kBlack, 0), 30 * 30 - 10 * 10);
}

TEST(Canvas, CircleCoversItsArea) {
  Canvas canvas(60, 60);
  const double r = 17.3;
  canvas.fillCircle({30.2, 29.6}, r, kBlack);
  const double area = std::numbers::pi * r * r;
  EXPECT_NEAR(totalInk(canvas.image()), area, 0.01 * area);
}

TEST(Canvas, ClipLimitsDrawing) {
  Canvas canvas(50, 50);
  canvas.pushClip({10.0, 20.0, 15.0, 5.0});
  canvas.fillRect({0.0, 0.0, 50.0, 50.0}, kBlack);
  canvas.popClip();
  const InkBox box = inkBounds(canvas.image(), kWhite, 0);
  EXPECT_EQ(box.x0, 10);
  EXPECT_EQ(box.x1, 24);
  EXPECT_EQ(box.y0, 20);
  EXPECT_EQ(box.y1, 24);
  EXPECT_EQ(box.inkPixels, 15 * 5);
}

TEST(Canvas, ArrowPointsFromTailToTip) {
  Canvas canvas(100, 40);
  ArrowStyle a;
  a.shaftWidth = 2.0;
  canvas.arrow({10.0, 20.0}, {90.0, 20.0}, a);
  const InkBox box = inkBounds(canvas.image(), kWhite, 10);
  EXPECT_NEAR(box.x0, 10, 1);
  EXPECT_NEAR(box.x1, 89, 1);
  // The head is wider than the shaft: more ink in a column near the tip than mid-shaft.
  const double head = columnInk(canvas.image(), 85), shaft = columnInk(canvas.image(), 50);
  EXPECT_NEAR(shaft, a.shaftWidth, 0.05);
  EXPECT_GT(head, 1.5 * shaft);
}

// ---------------------------------------------------------------------------------------------
// Text

TEST(Text, InkWidthIsCloseToTheMeasuredWidth) {
  Canvas canvas(400, 60);
  TextStyle t;
  t.size = 24.0;
  const std::string text = "Height h [mm]";
  const TextMetrics m = canvas.measureText(text, t);
  canvas.text({20.0, 40.0}, text, t);
  const InkBox box = inkBounds(canvas.image(), kWhite, 20);
  ASSERT_FALSE(box.empty());
  const double inkWidth = box.x1 - box.x0 + 1;
  // Ink is narrower than the advance only by the first and last side bearings (~0.1 em each).
  EXPECT_LE(inkWidth, m.width + 1.0);
  EXPECT_GE(inkWidth, m.width - 0.25 * t.size);
  EXPECT_NEAR(box.x0, 20.0, 0.15 * t.size);
  // Baseline alignment: capitals stand on the baseline, the bracket descends below it.
  EXPECT_LE(box.y0, 40 - int(0.6 * t.size));
  EXPECT_GT(box.y1, 40);
}

TEST(Text, KerningTightensPairsLikeAV) {
  // "AV" is kerned in every text face: the pair is narrower than its letters set apart.
  const auto font = Font::get(FontWeight::Regular, 50.0);
  EXPECT_LT(font->measure("AV").width, font->measure("A").width + font->measure("V").width - 1.0);
  EXPECT_NEAR(font->measure("ab").width, font->measure("a").width + font->measure("b").width, 1e-9);
}

TEST(Canvas, FarOffGeometryIsClippedSafely) {
  // Data far outside the axes: nothing to draw, and no overflow on the way.
  Canvas canvas(30, 30);
  Stroke s;
  s.width = 2.0;
  canvas.line({-1e30, 5.0}, {1e30, 5.0}, s);
  canvas.line({5.0, 1e300}, {6.0, -1e300}, s);
  const Point far[3] = {{1e20, 1e20}, {2e20, 1e20}, {1e20, 3e20}};
  canvas.fillPolygon(far, kBlack);
  canvas.fillCircle({1e15, 1e15}, 3.0, kBlack);
  TextStyle t;
  canvas.text({1e12, NAN}, "far", t);
  // The two lines cross the canvas and show (a row pair at y = 5, a column pair at x ≈ 5.5);
  // the far polygon, circle and text do not.
  EXPECT_NEAR(columnInk(canvas.image(), 15), 2.0, 0.05);
  EXPECT_NEAR(
      columnInk(canvas.image(), 4) + columnInk(canvas.image(), 5) + columnInk(canvas.image(), 6),
      2.0 * 30.0, 2.0);
  EXPECT_TRUE(inkBounds(canvas.image(), kWhite, 0, {8, 8, 30, 30}).empty());
}

TEST(Text, Utf8DecodesGreekAndMarksMalformedBytes) {
  const std::u32string s = decodeUtf8("σ₃₃ μ ‰ ² ³ · − Σ");
  EXPECT_EQ(s[0], U'\u03c3');
  EXPECT_EQ(s[1], U'\u2083');
  EXPECT_EQ(decodeUtf8("a\xff"
                       "b"),
            (std::u32string{U'a', U'\ufffd', U'b'}));
  EXPECT_EQ(decodeUtf8("\xcf"), std::u32string{U'\ufffd'});  // truncated σ
}

TEST(Text, LabelSymbolsHaveRealGlyphs) {
  // A character missing from the font would draw the same "missing" box as a private-use one.
  auto render = [](const std::string& s) {
    Canvas canvas(60, 60);
    TextStyle t;
    t.size = 30.0;
    canvas.text({10.0, 45.0}, s, t);
    return canvas.takeImage();
  };
  const Image missing = render("\U0010FFFD");  // a private-use code point, surely not in the font
  for (const char* symbol : {"σ", "μ", "‰", "²", "³", "·", "−", "Σ"}) {
    const Image img = render(symbol);
    EXPECT_GT(inkBounds(img, kWhite, 40).inkPixels, 0) << symbol;
    EXPECT_GT(compareImages(img, missing, 40).differing, 0) << symbol;
  }
}

TEST(Text, AlignmentPlacesTheBoxOnTheAnchor) {
  Canvas canvas(300, 200);
  TextStyle t;
  t.size = 20.0;
  t.hAlign = HAlign::Right;
  t.vAlign = VAlign::Top;
  const Rect box = canvas.text({200.0, 50.0}, "Tag", t);
  EXPECT_NEAR(box.right(), 200.0, 1e-9);
  EXPECT_NEAR(box.top(), 50.0, 1e-9);
  const InkBox ink = inkBounds(canvas.image(), kWhite, 40);
  EXPECT_LE(ink.x1, 200);
  EXPECT_GE(ink.y0, 50);
  t.hAlign = HAlign::Center;
  t.vAlign = VAlign::Middle;
  const TextMetrics m = canvas.measureText("Tag", t);
  const Rect centred = canvas.textBounds({100.0, 100.0}, "Tag", t);
  EXPECT_NEAR(centred.center().x, 100.0, 1e-9);
  // Middle: the cap height is centred on the anchor.
  EXPECT_NEAR(centred.top(), 100.0 + 0.5 * m.capHeight - m.ascent, 1e-9);
}

TEST(Text, RotatedLabelsRunVertically) {
  Canvas canvas(80, 300);
  TextStyle t;
  t.size = 20.0;
  t.angle = 90.0;
  t.hAlign = HAlign::Center;
  t.vAlign = VAlign::Middle;
  const std::string text = "Stress σ [kPa]";
  const TextMetrics m = canvas.measureText(text, t);
  canvas.text({40.0, 150.0}, text, t);
  const InkBox box = inkBounds(canvas.image(), kWhite, 20);
  const int height = box.y1 - box.y0 + 1, width = box.x1 - box.x0 + 1;
  EXPECT_GT(height, 3 * width);
  EXPECT_NEAR(height, m.width, 0.25 * t.size);
  EXPECT_NEAR(0.5 * (box.y0 + box.y1), 150.0, 0.2 * t.size);
  // Any other angle goes through the outlines and still inks a rotated box.
  Canvas tilted(300, 300);
  t.angle = 30.0;
  tilted.text({150.0, 150.0}, text, t);
  const InkBox tb = inkBounds(tilted.image(), kWhite, 20);
  const double c = std::cos(std::numbers::pi / 6), s = std::sin(std::numbers::pi / 6);
  EXPECT_NEAR(tb.x1 - tb.x0, m.width * c + m.capHeight * s, 0.3 * t.size);
}

TEST(Text, MissingFontFileNamesThePath) {
  const std::string path = "/nonexistent/fonts/NoSuchFont.ttf";
  try {
    Font::fromFile(path, 12.0);
    FAIL() << "expected FontError";
  } catch (const FontError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

// ---------------------------------------------------------------------------------------------
// Images

TEST(Canvas, BlitScalesWithEachFilter) {
  Image checker(2, 2);
  checker.set(0, 0, kBlack);
  checker.set(1, 1, kBlack);
  for (Filter f : {Filter::Nearest, Filter::Box, Filter::Bilinear}) {
    Canvas canvas(40, 40);
    canvas.blit(checker, Rect{10.0, 10.0, 20.0, 20.0}, f);
    // Quadrant centres keep the source pixel's colour; outside the target nothing changes.
    EXPECT_EQ(canvas.image().at(14, 14), kBlack);
    EXPECT_EQ(canvas.image().at(25, 14), kWhite);
    EXPECT_EQ(canvas.image().at(25, 25), kBlack);
    EXPECT_EQ(inkBounds(canvas.image(), kWhite, 0).x0, 10);
    EXPECT_EQ(inkBounds(canvas.image(), kWhite, 0).x1, 29);
  }
  // Shrinking with the box filter averages: a 2×2 checker into one pixel is mid grey.
  Canvas one(1, 1);
  one.blit(checker, Rect{0.0, 0.0, 1.0, 1.0}, Filter::Box);
  EXPECT_NEAR(one.image().at(0, 0).r, 127.5, 1.0);
}

// ---------------------------------------------------------------------------------------------
// Colour maps

double luminance(Rgba c) {
  return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
}

TEST(ColorMap, SequentialMapsGetLighterMonotonically) {
  for (ColorMap map : {ColorMap(viridis), ColorMap(magma), ColorMap(grayscale)}) {
    double previous = -1.0;
    for (int i = 0; i <= 100; ++i) {
      const double l = luminance(map(i / 100.0));
      EXPECT_GE(l, previous - 0.5) << i;  // half a level of rounding
      previous = l;
    }
    EXPECT_GT(luminance(map(1.0)) - luminance(map(0.0)), 150.0);
  }
}

TEST(ColorMap, JetRunsFromBlueToRed) {
  const Rgba lo = jet(0.0), hi = jet(1.0), mid = jet(0.5);
  EXPECT_GT(lo.b, 100);
  EXPECT_EQ(lo.r, 0);
  EXPECT_GT(hi.r, 100);
  EXPECT_EQ(hi.b, 0);
  EXPECT_GT(mid.g, 200);
}

TEST(ColorMap, ScaleClampsAndMarksMissingValues) {
  const ColorScale scale{-2.0, 6.0, viridis};
  EXPECT_EQ(scale(-10.0), viridis(0.0));
  EXPECT_EQ(scale(100.0), viridis(1.0));
  EXPECT_EQ(scale(2.0), viridis(0.5));
  EXPECT_EQ(scale(NAN).a, 0);
  EXPECT_EQ(bandColor(viridis, 0, 5), viridis(0.0));
  EXPECT_EQ(bandColor(viridis, 4, 5), viridis(1.0));
}

// ---------------------------------------------------------------------------------------------
// Inspection

TEST(Inspect, InkBoundsAndColourCounts) {
  Image img(20, 10);
  EXPECT_TRUE(inkBounds(img, kWhite, 0).empty());
  img.set(3, 4, {250, 250, 250, 255});
  img.set(15, 7, {10, 20, 200, 255});
  EXPECT_EQ(inkBounds(img, kWhite, 10).inkPixels, 1);  // the near-white pixel is within tolerance
  const InkBox box = inkBounds(img, kWhite, 0);
  EXPECT_EQ(box.inkPixels, 2);
  EXPECT_EQ(box.x0, 3);
  EXPECT_EQ(box.y0, 4);
  EXPECT_EQ(box.x1, 15);
  EXPECT_EQ(box.y1, 7);
  EXPECT_EQ(countColorPixels(img, {12, 18, 205, 255}, 5), 1);
  EXPECT_EQ(countColorPixels(img, {10, 20, 200, 255}, 0, {0, 0, 10, 10}), 0);
}

}  // namespace
}  // namespace granular::render
