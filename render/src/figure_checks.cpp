/// figure_checks.hpp.
#include "granular/render/figure_checks.hpp"

#include "granular/render/inspect.hpp"

namespace granular::render {

std::vector<std::string> figureProblems(const Image& image, const FigureExpectations& expect) {
  std::vector<std::string> problems;
  if (image.empty()) return {"the image is empty"};
  const double pixels = double(image.width) * image.height;
  const InkBox ink = inkBounds(image, expect.background, 8);
  if (ink.inkPixels < expect.minInkFraction * pixels) {
    problems.push_back("blank: only " + std::to_string(ink.inkPixels) + " inked pixels");
    return problems;
  }
  const int m = expect.borderMargin;
  if (ink.x0 < m || ink.y0 < m || ink.x1 >= image.width - m || ink.y1 >= image.height - m) {
    problems.push_back("clipped: ink reaches within " + std::to_string(m) + " px of the border");
  }
  if (expect.colorBarMap) {
    for (double t : {0.0, 1.0}) {
      const PixelRegion right{static_cast<int>(expect.colorBarFromX * image.width), 0, image.width,
                              image.height};
      const long n = countColorPixels(image, expect.colorBarMap(t), 6, right);
      if (n < expect.minBarPixels) {
        problems.push_back("no colour bar: the map's " + std::string(t == 0 ? "low" : "high") +
                           " end colour covers " + std::to_string(n) + " px");
      }
    }
  }
  const Rgba dark{0, 0, 0, 255};
  const int band = static_cast<int>(expect.titleBand * image.height);
  if (countColorPixels(image, dark, 60, {0, 0, image.width, band}) < expect.minTitlePixels) {
    problems.push_back("no title: no dark text in the top " + std::to_string(band) + " px");
  }
  if (countColorPixels(image, dark, 60, {0, image.height / 2, image.width, image.height}) <
      expect.minLabelPixels) {
    problems.push_back("no labels: no dark text in the lower half");
  }
  return problems;
}

}  // namespace granular::render
