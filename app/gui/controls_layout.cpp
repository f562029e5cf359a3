/// The controls panel's widths (controls_layout.hpp).
#include "controls_layout.hpp"

#include <algorithm>
#include <cmath>

namespace granular::gui {
namespace {

/// What the panel spends on other things than the field and its label [px].
float frame(const PanelSpacing& s) {
  return 2 * s.windowPadding + s.scrollbar + s.itemInnerSpacing;
}

}  // namespace

ControlsLayout controlsLayout(float widestLabel, float minFieldWidth, float minPanelWidth,
                              const PanelSpacing& spacing) {
  ControlsLayout layout;
  // Whole pixels, rounded up: a label a fraction of a pixel too wide is still cut.
  layout.panelWidth =
      std::ceil(std::max(minPanelWidth, widestLabel + minFieldWidth + frame(spacing)));
  layout.fieldWidth = layout.panelWidth - frame(spacing) - widestLabel;
  return layout;
}

float labelRoom(const ControlsLayout& layout, const PanelSpacing& spacing) {
  return layout.panelWidth - frame(spacing) - layout.fieldWidth;
}

}  // namespace granular::gui
