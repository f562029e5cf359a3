/// The controls panel's widths (app/gui/controls_layout.hpp): the widest label stands whole
/// beside a field, whatever the labels and ImGui's spacing; the window's own check of every label
/// at the default size is GuiUnderXvfb.*.
#include <gtest/gtest.h>

#include <cmath>

#include "controls_layout.hpp"

using granular::gui::ControlsLayout;
using granular::gui::controlsLayout;
using granular::gui::labelRoom;
using granular::gui::PanelSpacing;

// The panel holds, on one line: its padding on both sides, the scrollbar, a field, the spacing
// between field and label, and the label. Long labels widen the panel; short ones leave the
// minimum width, whose spare room goes to the fields.
TEST(GuiLayout, TheWidestLabelStandsWholeBesideAField) {
  const PanelSpacing imgui;  // Dear ImGui's default style: 8 + 8 padding, 4 spacing, 14 scrollbar
  for (float widest : {0.0f, 100.0f, 174.0f, 210.0f, 210.3f, 500.0f}) {
    SCOPED_TRACE(widest);
    const ControlsLayout layout = controlsLayout(widest, 130, 340, imgui);
    EXPECT_GE(labelRoom(layout, imgui), widest);
    EXPECT_GE(layout.fieldWidth, 130.0f);
    EXPECT_GE(layout.panelWidth, 340.0f);
    EXPECT_EQ(layout.panelWidth, std::round(layout.panelWidth));  // whole pixels
    EXPECT_FLOAT_EQ(8 + layout.fieldWidth + 4 + labelRoom(layout, imgui) + 14 + 8,
                    layout.panelWidth);
    // No wider than needed: the minimum, or the label and the smallest field exactly.
    EXPECT_LT(layout.panelWidth, std::max(340.0f, widest + 130 + 34) + 1);
  }
  // The labels of the default window (30 characters of 7 px, ImGui's own font, at the longest)
  // fit 34 px past the 340 px the panel had, where they were cut after 13 characters.
  EXPECT_EQ(controlsLayout(210, 130, 340, imgui).panelWidth, 374.0f);
  // A wider style (larger padding, a thicker scrollbar) widens the panel, not eats the label.
  const PanelSpacing wide{20, 10, 30};
  EXPECT_GE(labelRoom(controlsLayout(210, 130, 340, wide), wide), 210.0f);
}
