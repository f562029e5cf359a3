#pragma once
/// Internal: the legend of line plots (plot.hpp): size, placement over the least data, drawing.
#include <span>
#include <string>
#include <vector>

#include "granular/render/axes.hpp"
#include "granular/render/plot.hpp"

namespace granular::render::detail {

struct LegendEntry {
  std::string label;
  Rgba color;
  double width = 0.0;  ///< line width [px]; 0 = no line sample
  Series::Dash dash = Series::Solid;
  Marker marker = Marker::None;
  double markerSize = 0.0;  ///< [px]
};

struct LegendLayout {
  double width = 0.0, height = 0.0;  ///< framed box [px]
  double font = 0.0;                 ///< label size [px]
  double pad = 0.0;                  ///< frame → content [px]
  double handle = 0.0;               ///< line sample length [px]
  double gap = 0.0;                  ///< sample → label [px]
  double row = 0.0;                  ///< row pitch [px]
};

LegendLayout legendLayout(std::span<const LegendEntry> entries, const FigureStyle& style);
/// The box for a position; Auto scores nine spots by the obstacle points they cover and reports
/// the best count in `hidden` (when not null).
Rect placeLegend(const LegendLayout& layout, const Rect& area, LegendPosition position,
                 std::span<const Point> obstacles, const FigureStyle& style, long* hidden);
void drawLegend(Canvas& canvas, const Rect& box, const LegendLayout& layout,
                std::span<const LegendEntry> entries, const FigureStyle& style);

}  // namespace granular::render::detail
