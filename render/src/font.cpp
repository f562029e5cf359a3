/// FreeType text (font.hpp).
///
/// Sections: UTF-8 decoding · the FreeType library and font cache · glyph metrics and layout ·
/// coverage rasters · outlines.
///
/// Glyphs are hinted "light" (vertical only): stems and the baseline snap to whole pixels, which
/// keeps small text crisp, while horizontal shapes and advances stay unhinted so that spacing and
/// measured widths do not depend on the size. Glyphs are cached at four horizontal sub-pixel
/// phases, so a string's glyphs sit within 1/8 px of their exact pen positions.
#include "granular/render/font.hpp"

#include <ft2build.h>
#include FT_FREETYPE_H
#include FT_OUTLINE_H
#include FT_TRUETYPE_TABLES_H

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <unordered_map>

// Set by render/CMakeLists.txt; the Debian location otherwise.
#ifndef GRANULAR_FONT_DIR
#define GRANULAR_FONT_DIR "/usr/share/fonts/truetype/dejavu"
#endif

namespace granular::render {

// ---------------------------------------------------------------------------------------------
// UTF-8 decoding

std::u32string decodeUtf8(std::string_view s) {
  constexpr char32_t kReplacement = 0xFFFD;
  std::u32string out;
  out.reserve(s.size());
  std::size_t i = 0;
  while (i < s.size()) {
    const auto c = static_cast<unsigned char>(s[i]);
    int extra = 0;
    char32_t cp = 0;
    if (c < 0x80) {
      cp = c;
    } else if ((c & 0xE0) == 0xC0) {
      extra = 1;
      cp = c & 0x1F;
    } else if ((c & 0xF0) == 0xE0) {
      extra = 2;
      cp = c & 0x0F;
    } else if ((c & 0xF8) == 0xF0) {
      extra = 3;
      cp = c & 0x07;
    } else {
      out.push_back(kReplacement);
      ++i;
      continue;
    }
    if (i + std::size_t(extra) >= s.size()) {  // truncated sequence at the end
      out.push_back(kReplacement);
      ++i;
      continue;
    }
    bool ok = true;
    for (int k = 1; k <= extra; ++k) {
      const auto cc = static_cast<unsigned char>(s[i + k]);
      if ((cc & 0xC0) != 0x80) {
        ok = false;
        break;
      }
      cp = (cp << 6) | (cc & 0x3F);
    }
    // Overlong forms, surrogates and values past U+10FFFF are malformed too.
    static constexpr char32_t kMinForLength[4] = {0, 0x80, 0x800, 0x10000};
    if (!ok || cp < kMinForLength[extra] || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) {
      out.push_back(kReplacement);
      ++i;
      continue;
    }
    out.push_back(cp);
    i += std::size_t(extra) + 1;
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// The FreeType library and the font cache

namespace {

/// FreeType's library object is not thread-safe for creating and destroying faces: one mutex.
std::mutex& libraryMutex() {
  static std::mutex m;
  return m;
}

FT_Library library() {
  static FT_Library lib = [] {
    FT_Library l = nullptr;
    if (FT_Init_FreeType(&l) != 0) throw FontError("FreeType could not be initialised");
    return l;
  }();
  return lib;
}

struct GlyphBitmap {
  int left = 0;  ///< column of the first bitmap column relative to the pen [px]
  int top = 0;   ///< rows from the first bitmap row up to the baseline [px]
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> bits;
};

struct GlyphInfo {
  FT_UInt index = 0;
  double advance = 0.0;  ///< unhinted advance [px]
};

using Contours = std::vector<std::vector<Point>>;

}  // namespace

struct Font::Impl {
  FT_Face face = nullptr;
  double size = 0.0;
  double ascent = 0.0, descent = 0.0, capHeight = 0.0;
  bool hasKerning = false;

  mutable std::mutex mutex;  ///< guards the face and the caches
  mutable std::unordered_map<char32_t, GlyphInfo> infos;
  mutable std::unordered_map<std::uint64_t, GlyphBitmap> bitmaps;  ///< key: index · 4 + phase
  mutable std::unordered_map<FT_UInt, Contours> outlines;

  ~Impl() {
    if (face) {
      std::lock_guard lock(libraryMutex());
      FT_Done_Face(face);
    }
  }

  // -------------------------------------------------------------------------------------------
  // Glyph metrics and layout (callers hold `mutex`)

  const GlyphInfo& info(char32_t cp) const {
    auto it = infos.find(cp);
    if (it != infos.end()) return it->second;
    GlyphInfo g;
    g.index = FT_Get_Char_Index(face, cp);
    if (FT_Load_Glyph(face, g.index, FT_LOAD_NO_BITMAP | FT_LOAD_TARGET_LIGHT) == 0) {
      g.advance = double(face->glyph->linearHoriAdvance) / 65536.0;
    }
    return infos.emplace(cp, g).first->second;
  }

  /// Pen position of every glyph of the string, starting at x0; returns the end position.
  double layout(const std::u32string& text, double x0, std::vector<double>* pens,
                std::vector<FT_UInt>* indices) const {
    double pen = x0;
    FT_UInt previous = 0;
    for (char32_t cp : text) {
      const GlyphInfo& g = info(cp);
      if (hasKerning && previous != 0 && g.index != 0) {
        FT_Vector delta{0, 0};
        if (FT_Get_Kerning(face, previous, g.index, FT_KERNING_UNFITTED, &delta) == 0) {
          pen += double(delta.x) / 64.0;
        }
      }
      if (pens) pens->push_back(pen);
      if (indices) indices->push_back(g.index);
      pen += g.advance;
      previous = g.index;
    }
    return pen;
  }

  // -------------------------------------------------------------------------------------------
  // Coverage rasters

  const GlyphBitmap& bitmap(FT_UInt index, int phase) const {
    const std::uint64_t key = std::uint64_t(index) * 4 + std::uint64_t(phase);
    auto it = bitmaps.find(key);
    if (it != bitmaps.end()) return it->second;
    GlyphBitmap b;
    if (FT_Load_Glyph(face, index, FT_LOAD_NO_BITMAP | FT_LOAD_TARGET_LIGHT) == 0 &&
        face->glyph->format == FT_GLYPH_FORMAT_OUTLINE) {
      FT_Outline_Translate(&face->glyph->outline, phase * 16, 0);  // quarter pixel in 26.6
      if (FT_Render_Glyph(face->glyph, FT_RENDER_MODE_NORMAL) == 0) {
        const FT_Bitmap& bm = face->glyph->bitmap;
        b.left = face->glyph->bitmap_left;
        b.top = face->glyph->bitmap_top;
        b.width = int(bm.width);
        b.height = int(bm.rows);
        b.bits.resize(std::size_t(b.width) * b.height);
        for (int y = 0; y < b.height; ++y) {
          const unsigned char* row = bm.buffer + std::ptrdiff_t(y) * bm.pitch;
          std::copy(row, row + b.width, b.bits.begin() + std::ptrdiff_t(y) * b.width);
        }
      }
    }
    return bitmaps.emplace(key, std::move(b)).first->second;
  }

  // -------------------------------------------------------------------------------------------
  // Outlines

  const Contours& outline(FT_UInt index) const {
    auto it = outlines.find(index);
    if (it != outlines.end()) return it->second;
    Contours contours;
    if (FT_Load_Glyph(face, index, FT_LOAD_NO_BITMAP | FT_LOAD_NO_HINTING) == 0 &&
        face->glyph->format == FT_GLYPH_FORMAT_OUTLINE) {
      FT_Outline_Funcs funcs{};
      funcs.move_to = [](const FT_Vector* to, void* user) {
        auto* c = static_cast<Contours*>(user);
        c->push_back({toPoint(to)});
        return 0;
      };
      funcs.line_to = [](const FT_Vector* to, void* user) {
        static_cast<Contours*>(user)->back().push_back(toPoint(to));
        return 0;
      };
      funcs.conic_to = [](const FT_Vector* control, const FT_Vector* to, void* user) {
        auto& poly = static_cast<Contours*>(user)->back();
        const Point p0 = poly.back(), p1 = toPoint(control), p2 = toPoint(to);
        const int n = segmentsFor(length(p0 - 2.0 * p1 + p2) / 4.0);
        for (int k = 1; k <= n; ++k) {
          const double t = double(k) / n, u = 1.0 - t;
          poly.push_back(u * u * p0 + 2.0 * u * t * p1 + t * t * p2);
        }
        return 0;
      };
      funcs.cubic_to = [](const FT_Vector* c1, const FT_Vector* c2, const FT_Vector* to,
                          void* user) {
        auto& poly = static_cast<Contours*>(user)->back();
        const Point p0 = poly.back(), p1 = toPoint(c1), p2 = toPoint(c2), p3 = toPoint(to);
        const double bend = 0.75 * std::max(length(p0 - 2.0 * p1 + p2), length(p1 - 2.0 * p2 + p3));
        const int n = segmentsFor(bend);
        for (int k = 1; k <= n; ++k) {
          const double t = double(k) / n, u = 1.0 - t;
          poly.push_back(u * u * u * p0 + 3.0 * u * u * t * p1 + 3.0 * u * t * t * p2 +
                         t * t * t * p3);
        }
        return 0;
      };
      FT_Outline_Decompose(&face->glyph->outline, &funcs, &contours);
    }
    return outlines.emplace(index, std::move(contours)).first->second;
  }

  /// 26.6 font coordinates (y up) to pixels (y down).
  static Point toPoint(const FT_Vector* v) { return {double(v->x) / 64.0, -double(v->y) / 64.0}; }
  /// Segments for a curve bending `bend` px off its chord: the flattening error falls with the
  /// square of the count; 0.1 px is below what anti-aliasing shows.
  static int segmentsFor(double bend) {
    return std::clamp(int(std::ceil(std::sqrt(bend / 0.1))), 1, 32);
  }
};

Font::Font(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Font::~Font() = default;

std::filesystem::path Font::file(FontWeight weight) {
  const std::filesystem::path dir = GRANULAR_FONT_DIR;
  return dir / (weight == FontWeight::Bold ? "DejaVuSans-Bold.ttf" : "DejaVuSans.ttf");
}

std::shared_ptr<const Font> Font::get(FontWeight weight, double pixelSize) {
  const long size64 = std::max(64L, std::lround(pixelSize * 64.0));  // at least 1 px
  static std::mutex cacheMutex;
  static std::map<std::pair<int, long>, std::shared_ptr<const Font>> cache;
  std::lock_guard cacheLock(cacheMutex);
  const auto key = std::make_pair(int(weight), size64);
  if (auto it = cache.find(key); it != cache.end()) return it->second;
  auto font = fromFile(file(weight), double(size64) / 64.0);
  cache.emplace(key, font);
  return font;
}

std::shared_ptr<const Font> Font::fromFile(const std::filesystem::path& path, double pixelSize) {
  const long size64 = std::max(64L, std::lround(pixelSize * 64.0));  // at least 1 px
  auto impl = std::make_unique<Impl>();
  {
    std::lock_guard lock(libraryMutex());
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) {
      std::string msg = "font file not found: ";
      msg += path.string();
      msg += " (DejaVu Sans comes with the Debian package fonts-dejavu-core)";
      throw FontError(msg);
    }
    const FT_Error err = FT_New_Face(library(), path.c_str(), 0, &impl->face);
    if (err != 0) {
      impl->face = nullptr;
      std::string msg = "cannot load font ";
      msg += path.string();
      msg += ": FreeType error ";
      msg += std::to_string(err);
      throw FontError(msg);
    }
  }
  FT_Face face = impl->face;
  FT_Set_Char_Size(face, 0, size64, 72, 72);  // 72 dpi: one point per pixel
  impl->size = double(size64) / 64.0;
  const FT_Fixed yScale = face->size->metrics.y_scale;
  impl->ascent = double(FT_MulFix(face->ascender, yScale)) / 64.0;
  impl->descent = -double(FT_MulFix(face->descender, yScale)) / 64.0;
  const auto* os2 = static_cast<const TT_OS2*>(FT_Get_Sfnt_Table(face, FT_SFNT_OS2));
  impl->capHeight = (os2 && os2->version >= 2 && os2->sCapHeight > 0)
                        ? double(FT_MulFix(os2->sCapHeight, yScale)) / 64.0
                        : 0.73 * impl->size;
  impl->hasKerning = FT_HAS_KERNING(face);
  return std::shared_ptr<const Font>(new Font(std::move(impl)));
}

double Font::pixelSize() const {
  return impl_->size;
}

TextMetrics Font::measure(std::string_view utf8) const {
  const std::u32string text = decodeUtf8(utf8);
  std::lock_guard lock(impl_->mutex);
  TextMetrics m;
  m.width = impl_->layout(text, 0.0, nullptr, nullptr);
  m.ascent = impl_->ascent;
  m.descent = impl_->descent;
  m.capHeight = impl_->capHeight;
  return m;
}

TextRaster Font::rasterize(std::string_view utf8, double subpixelX) const {
  const std::u32string text = decodeUtf8(utf8);
  std::lock_guard lock(impl_->mutex);
  std::vector<double> pens;
  std::vector<FT_UInt> indices;
  impl_->layout(text, subpixelX, &pens, &indices);

  struct Placed {
    const GlyphBitmap* bitmap;
    int x, y;  // top-left of the bitmap relative to (pen origin, baseline)
  };
  std::vector<Placed> placed;
  placed.reserve(pens.size());
  int x0 = 0, x1 = 0, y0 = 0, y1 = 0;
  bool any = false;
  for (std::size_t i = 0; i < pens.size(); ++i) {
    int column = int(std::floor(pens[i]));
    int phase = int(std::lround((pens[i] - column) * 4.0));
    if (phase == 4) {
      ++column;
      phase = 0;
    }
    const GlyphBitmap& b = impl_->bitmap(indices[i], phase);
    if (b.width == 0 || b.height == 0) continue;
    const Placed p{&b, column + b.left, -b.top};
    placed.push_back(p);
    if (!any) {
      x0 = p.x, x1 = p.x + b.width, y0 = p.y, y1 = p.y + b.height;
      any = true;
    } else {
      x0 = std::min(x0, p.x), x1 = std::max(x1, p.x + b.width);
      y0 = std::min(y0, p.y), y1 = std::max(y1, p.y + b.height);
    }
  }
  TextRaster r;
  if (!any) return r;
  r.width = x1 - x0;
  r.height = y1 - y0;
  r.originX = -x0;
  r.baselineY = -y0;
  r.coverage.assign(std::size_t(r.width) * r.height, 0);
  for (const Placed& p : placed) {
    const GlyphBitmap& b = *p.bitmap;
    for (int y = 0; y < b.height; ++y) {
      std::uint8_t* dst = r.coverage.data() + std::size_t(p.y - y0 + y) * r.width + (p.x - x0);
      const std::uint8_t* src = b.bits.data() + std::size_t(y) * b.width;
      for (int x = 0; x < b.width; ++x) {
        // Saturating sum: kerned neighbours may overlap by a pixel.
        dst[x] = std::uint8_t(std::min(255, int(dst[x]) + int(src[x])));
      }
    }
  }
  return r;
}

std::vector<std::vector<Point>> Font::outline(std::string_view utf8) const {
  const std::u32string text = decodeUtf8(utf8);
  std::lock_guard lock(impl_->mutex);
  std::vector<double> pens;
  std::vector<FT_UInt> indices;
  impl_->layout(text, 0.0, &pens, &indices);
  std::vector<std::vector<Point>> all;
  for (std::size_t i = 0; i < pens.size(); ++i) {
    for (const auto& contour : impl_->outline(indices[i])) {
      std::vector<Point> moved;
      moved.reserve(contour.size());
      for (Point p : contour) moved.push_back({p.x + pens[i], p.y});
      all.push_back(std::move(moved));
    }
  }
  return all;
}

}  // namespace granular::render
