/// Checks a screenshot of granular-gui (tests/gui_xvfb_test.sh): the 3-D view shows particles
/// (many pixels of the colour map, on the view's white background), and the control, plot and
/// status panels are drawn (ImGui's dark windows with light text). The layout is the window's:
/// controls 340 px wide on the left, status bar 30 px and plots 250 px at the bottom.
#include <algorithm>
#include <cstdio>
#include <exception>
#include <string>

#include "granular/render/image.hpp"

using granular::render::Image;
using granular::render::Rgba;

namespace {

bool coloured(Rgba c) {  // viridis: clearly not grey
  const int hi = std::max({int(c.r), int(c.g), int(c.b)});
  const int lo = std::min({int(c.r), int(c.g), int(c.b)});
  return hi - lo > 50;
}
bool dark(Rgba c) {
  return c.r < 70 && c.g < 70 && c.b < 90;
}
bool light(Rgba c) {
  return c.r > 170 && c.g > 170 && c.b > 170;
}

struct Count {
  long total = 0, colouredPixels = 0, darkPixels = 0, lightPixels = 0, white = 0;
};

Count count(const Image& image, int x0, int y0, int x1, int y1) {
  Count n;
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) {
      const Rgba c = image.at(x, y);
      ++n.total;
      n.colouredPixels += coloured(c);
      n.darkPixels += dark(c);
      n.lightPixels += light(c);
      n.white += c.r == 255 && c.g == 255 && c.b == 255;
    }
  }
  return n;
}

}  // namespace

int main(int argc, char** argv) {
  const bool viewOnly = argc == 3 && std::string(argv[1]) == "--view";
  if (argc != 2 && !viewOnly) {
    std::fprintf(stderr, "usage: granular_gui_screenshot_check [--view] SCREENSHOT.png\n");
    return 2;
  }
  try {
    const Image image = granular::render::readPng(argv[argc - 1]);
    if (viewOnly) {  // the 3-D view alone (save-view): white background, coloured particles
      const Count view = count(image, 0, 0, image.width, image.height);
      std::printf("saved view %d x %d: %ld coloured px, %ld white\n", image.width, image.height,
                  view.colouredPixels, view.white);
      const bool ok = view.white > view.total / 3 && view.colouredPixels > 4000;
      if (!ok) std::fprintf(stderr, "FAILED: the saved 3-D view shows no particles\n");
      return ok ? 0 : 1;
    }
    const int w = image.width, h = image.height;
    if (w < 800 || h < 600) {
      std::fprintf(stderr, "screenshot %d x %d: smaller than the window's 800 x 600\n", w, h);
      return 1;
    }
    const Count view = count(image, 340, 0, w, h - 280);
    const Count controls = count(image, 0, 0, 340, h - 30);
    const Count plots = count(image, 340, h - 280, w, h - 30);
    const Count status = count(image, 0, h - 30, w, h);
    std::printf("view: %ld coloured px, %ld white of %ld\n", view.colouredPixels, view.white,
                view.total);
    std::printf("controls: %ld dark, %ld light of %ld\n", controls.darkPixels, controls.lightPixels,
                controls.total);
    std::printf("plots: %ld dark, %ld light of %ld\n", plots.darkPixels, plots.lightPixels,
                plots.total);
    std::printf("status: %ld dark, %ld light of %ld\n", status.darkPixels, status.lightPixels,
                status.total);
    bool ok = true;
    auto require = [&](bool condition, const char* what) {
      if (!condition) std::fprintf(stderr, "FAILED: %s\n", what);
      ok = ok && condition;
    };
    require(view.white > view.total / 3, "the 3-D view's white background");
    require(view.colouredPixels > 2000, "particles coloured by the map in the 3-D view");
    require(controls.darkPixels > controls.total / 3, "the controls panel");
    require(controls.lightPixels > 1000, "text in the controls panel");
    require(plots.darkPixels > plots.total / 3, "the plots panel");
    require(plots.lightPixels > 200, "titles and curves in the plots panel");
    require(status.lightPixels > 300, "text in the status bar");
    return ok ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "granular_gui_screenshot_check: %s\n", e.what());
    return 1;
  }
}
