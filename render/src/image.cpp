/// Image basics, PNG I/O and comparison (image.hpp).
#include "granular/render/image.hpp"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <ostream>

#include "granular/output_file.hpp"

namespace granular::render {

Image::Image(int w, int h, Rgba fill) : width(w), height(h), pixels(std::size_t(w) * h * 4) {
  for (std::size_t i = 0; i < pixels.size(); i += 4) {
    pixels[i] = fill.r;
    pixels[i + 1] = fill.g;
    pixels[i + 2] = fill.b;
    pixels[i + 3] = fill.a;
  }
}

Rgba Image::at(int x, int y) const {
  const std::size_t i = (std::size_t(y) * width + x) * 4;
  return {pixels[i], pixels[i + 1], pixels[i + 2], pixels[i + 3]};
}

void Image::set(int x, int y, Rgba c) {
  const std::size_t i = (std::size_t(y) * width + x) * 4;
  pixels[i] = c.r;
  pixels[i + 1] = c.g;
  pixels[i + 2] = c.b;
  pixels[i + 3] = c.a;
}

namespace {

struct FileCloser {
  void operator()(std::FILE* f) const {
    if (f) std::fclose(f);
  }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

}  // namespace

namespace {

/// libpng's output into the temporary of an AtomicFile, whose stream keeps any failure for
/// commit() to report with the operating system's reason.
void writeToStream(png_structp png, png_bytep data, png_size_t size) {
  static_cast<std::ostream*>(png_get_io_ptr(png))
      ->write(reinterpret_cast<const char*>(data), std::streamsize(size));
}
void flushStream(png_structp) {}

}  // namespace

void writePng(const Image& image, const std::filesystem::path& file, double dpi,
              int compressionLevel) {
  if (image.empty()) throw ImageError(file.string() + ": refusing to write an empty image");
  AtomicFile out(file);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_write_struct(&png, &info);
    throw ImageError(file.string() + ": libpng could not start");
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw ImageError(file.string() + ": libpng failed while writing");
  }
  png_set_write_fn(png, &out.stream(), writeToStream, flushStream);
  png_set_compression_level(png, std::clamp(compressionLevel, 0, 9));  // 1: encoding is costly
  // The 'up' filter alone: as small as libpng's adaptive choice on figures, faster to encode.
  png_set_filter(png, 0, PNG_FILTER_UP);
  png_set_IHDR(png, info, image.width, image.height, 8, PNG_COLOR_TYPE_RGB_ALPHA,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  const auto ppm = static_cast<png_uint_32>(std::lround(dpi / 0.0254));
  png_set_pHYs(png, info, ppm, ppm, PNG_RESOLUTION_METER);
  png_write_info(png, info);
  for (int y = 0; y < image.height; ++y) {
    png_write_row(png, image.pixels.data() + std::size_t(y) * image.width * 4);
  }
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  out.commit();
}

Image readPng(const std::filesystem::path& file) {
  File f(std::fopen(file.c_str(), "rb"));
  if (!f) throw ImageError(file.string() + ": cannot open");
  unsigned char signature[8];
  if (std::fread(signature, 1, 8, f.get()) != 8 || png_sig_cmp(signature, 0, 8) != 0) {
    throw ImageError(file.string() + ": not a PNG file");
  }
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw ImageError(file.string() + ": libpng could not start");
  }
  Image image;
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw ImageError(file.string() + ": corrupted PNG");
  }
  png_init_io(png, f.get());
  png_set_sig_bytes(png, 8);
  png_read_info(png, info);
  // Normalise to 8-bit RGBA whatever was stored.
  png_set_expand(png);
  png_set_strip_16(png);
  png_set_gray_to_rgb(png);
  png_set_add_alpha(png, 0xff, PNG_FILLER_AFTER);
  png_read_update_info(png, info);
  image.width = static_cast<int>(png_get_image_width(png, info));
  image.height = static_cast<int>(png_get_image_height(png, info));
  image.pixels.resize(std::size_t(image.width) * image.height * 4);
  std::vector<png_bytep> rows(image.height);
  for (int y = 0; y < image.height; ++y)
    rows[y] = image.pixels.data() + std::size_t(y) * image.width * 4;
  png_read_image(png, rows.data());
  png_destroy_read_struct(&png, &info, nullptr);
  return image;
}

ImageDiff compareImages(const Image& actual, const Image& expected, int tolerance) {
  ImageDiff d;
  d.sameSize = actual.width == expected.width && actual.height == expected.height;
  if (!d.sameSize) {
    d.fraction = 1.0;
    return d;
  }
  d.diff = Image(expected.width, expected.height);
  for (int y = 0; y < expected.height; ++y) {
    for (int x = 0; x < expected.width; ++x) {
      const Rgba a = actual.at(x, y), e = expected.at(x, y);
      const int delta = std::max(
          {std::abs(a.r - e.r), std::abs(a.g - e.g), std::abs(a.b - e.b), std::abs(a.a - e.a)});
      d.maxChannelDelta = std::max(d.maxChannelDelta, delta);
      if (delta > tolerance) {
        ++d.differing;
        d.diff.set(x, y, {255, 0, 0, 255});
      } else {
        // Faded expected image, so the differing pixels stand out in context.
        auto fade = [](std::uint8_t c) { return static_cast<std::uint8_t>(191 + c / 4); };
        d.diff.set(x, y, {fade(e.r), fade(e.g), fade(e.b), 255});
      }
    }
  }
  d.fraction = double(d.differing) / (double(expected.width) * expected.height);
  return d;
}

}  // namespace granular::render
