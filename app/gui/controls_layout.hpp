#pragma once
/// The width of the window's controls panel and of its fields, from the widest label beside a
/// field, so that every label stands whole (ImGui cuts off what runs past the panel's edge).
/// Pure arithmetic on pixel widths: the window measures the labels (ImGui::CalcTextSize).
namespace granular::gui {

/// ImGui's spacing around a field and its label [px].
struct PanelSpacing {
  float windowPadding = 8;     ///< left and right of the content (style.WindowPadding.x)
  float itemInnerSpacing = 4;  ///< between a field and its label (style.ItemInnerSpacing.x)
  float scrollbar = 14;        ///< the vertical scrollbar, kept free (style.ScrollbarSize)
};

struct ControlsLayout {
  float panelWidth = 0;  ///< [px]
  float fieldWidth = 0;  ///< every field, combo and slider (ImGui::PushItemWidth) [px]
};

/// The narrowest panel of at least `minPanelWidth` in which a field of at least `minFieldWidth`
/// and the widest label beside it fit; room beyond that goes to the fields.
ControlsLayout controlsLayout(float widestLabel, float minFieldWidth, float minPanelWidth,
                              const PanelSpacing& spacing);

/// The room a label has beside a field in `layout` [px].
float labelRoom(const ControlsLayout& layout, const PanelSpacing& spacing);

}  // namespace granular::gui
