// Helpers shared by the scene panels: the 3D inspector view with orbit/zoom by mouse, colour
// bars, and a pixel-picking image widget. No algorithms.
#pragma once

#include "gui/scene_view.h"
#include "gui/ui_state.h"
#include "pipeline/workbench.h"
#include "render/frame_analysis.h"

#include "core/color.h"
#include "core/fields.h"

#include <imgui.h>

#include <glm/vec3.hpp>

#include <string>
#include <vector>

namespace app {

// Shows a SceneView texture (drawn with ui.inspect.camera, at the screen's pixels) filling
// `size` (UI units); dragging orbits, the wheel zooms. Returns true and sets (px, py) (UI units
// from the top left) on a click.
bool inspectorImage(Workbench& wb, UiShared& ui, SceneView& view, ImVec2 size, float pointSize,
                    float& px, float& py);
using core::luminance; // the scalar the scalar views and heatmaps show
// A horizontal colour bar of colorRamp with its end labels.
void rampBar(float lo, float hi, const char* unit);
// Shows an RGBA texture (row 0 at the top) of w × h scaled to `width`; returns true and the
// pixel on a click (uv: the same as a fraction of the image, when non-null). Dragging reports
// the mouse delta through `drag` (pixels) when non-null. `id` names the widget: it must not
// change while the image does (a new texture or size while the button is held).
bool pickImage(const char* id, GLuint tex, int w, int h, float width, int& px, int& py,
               bool flipY = false, ImVec2* drag = nullptr, float* wheel = nullptr,
               ImVec2* uv = nullptr);
// An ImGui combo over the values 0 .. N-1 of enum E, labelled by `names`.
template <class E, size_t N>
bool comboEnum(const char* label, E& value, const char* const (&names)[N]) {
    int i = static_cast<int>(value);
    if (!ImGui::Combo(label, &i, names, static_cast<int>(N))) return false;
    value = static_cast<E>(i);
    return true;
}
// ImGui::SameLine() when an item of `width` pixels still fits on the current line, so rows of
// controls wrap in narrow areas instead of running off the edge.
void sameLineIfFits(float width);
// ImGui::SetNextItemWidth(width), narrowed where the item and its label would run past the
// window's visible right edge (a wide field in a narrow area would make the whole panel scroll
// sideways); fittingWidth is that width, for items sized by hand (progress bars, images).
// Never under four characters.
void setItemWidth(float width, const char* label);
float fittingWidth(float width, const char* label = "");
// The next item (`width` px wide with `label`) on the line of the one before when it fits
// there (sameLineIfFits), at setItemWidth's width.
void sameLineItem(float width, const char* label);
// From the cursor to the window's visible right edge, in pixels, a vertical scrollbar's width
// left free whether or not one is shown: an item sized by it keeps its size when the scrollbar
// comes or goes (sized by the content region, an item whose height needs the scrollbar only
// at the wider width makes the panel flip between the two layouts every frame).
float visibleWidth();
// Where the last item was drawn (screen px), recorded by panels for clicks in tests.
Rect lastItem();
// Edit fields that commit when the edit is done — Enter or focus loss — not on every key
// (a setting that restarts work would restart per keystroke). The +/- step buttons of the
// integer fields commit at once. Each returns true when the value was committed.
bool inputIntCommitted(const char* label, int* v, int step = 1, int stepFast = 100);
bool inputInt2Committed(const char* label, int v[2]);
bool inputTextCommitted(const char* label, char* buffer, size_t size);
// A file's path field for the setting `value`: the field shows the value again whenever it
// changed other than through the field (a restored session, a replayed capture, a dropped
// file), and a commit sets it (returns true).
bool pathFieldCommitted(const char* label, char* buffer, size_t size, std::string& value);
// A bar chart with axes: the y name and maximum above, the first and last x values and the x
// name below (ImGui's histogram has none); hovering a bar shows its value.
void histogram(const char* id, const std::vector<float>& values, ImVec2 size, const char* xName,
               int xFirst, const char* yName);
// A line of text wrapped at the window's visible right edge (ImGui::TextWrapped wraps at the
// content region's, which grows once anything ran over); a hint or status line: the same in
// the disabled text colour.
void wrappedText(const char* fmt, ...) IM_FMTARGS(1);
void hintText(const char* fmt, ...) IM_FMTARGS(1);
// wrappedText in `colour` (a problem, a warning, a state).
void colouredText(const ImVec4& colour, const char* fmt, ...) IM_FMTARGS(2);
// `text` with line breaks where a line would be wider than `width` pixels in the current font:
// at spaces only (ImGui's own wrapping also breaks after '.' and ',', splitting numbers such as
// 1.66), inside a word only where the word alone is wider; the spaces at a break are dropped.
// Written here since ImGui 1.86 has no such option.
std::string breakLines(const std::string& text, float width);
// `text` cut with "..." where it is wider than `width` pixels (one line that must not wrap:
// a tree node's name, a map's title); unchanged where it fits.
std::string cutToWidth(std::string text, float width);

// Widths of widgets, for sameLineIfFits: a checkbox (or radio button) with `label`, a button,
// and a framed item of `frame` pixels with its label.
float checkboxWidth(const char* label);
float buttonWidth(const char* label);
float itemWidth(float frame, const char* label);

// A combo of every value of a named enum (core/fields.h: enumNames), `width` pixels wide, on
// the same line as the item before when it fits; true when the user picked another value.
template <core::NamedEnum E> bool enumCombo(const char* label, E& value, float width) {
    sameLineItem(width, label);
    bool changed = false;
    if (ImGui::BeginCombo(label, core::nameOf(value))) {
        for (const auto& [v, name] : enumNames(E{}))
            if (ImGui::Selectable(name, value == v) && value != v) {
                value = v;
                changed = true;
            }
        ImGui::EndCombo();
    }
    return changed;
}
// The directions scored per collision by the expected-value exits of the CPU histogram walks
// (pathtrace.h, ExpectedExits; 0: the actual exits), as the pencil plot's reference and the
// slice offer it, with its tooltip; on the same line when it fits.
bool exitSamplesInput(int& samples);
// The BSSRDF integration's sampling (uniform area | disk probe rays) and, for disk sampling, its
// probe-axis scheme, as the Lit spheres and Render panels offer them.
void samplingChoice(const char* label, integrate::Sampling& sampling, sampling::AxisScheme& axes);
// Makes ui.inspect.camera frame the scene mesh (once).
void ensureInspectCamera(Workbench& wb, UiShared& ui);

} // namespace app
