// plot: drawPlot(), the ImGui half of the plot widget. Layout, grid, labels, bands, curves,
// legend and hover readout drawn into the current window's ImDrawList; the geometry comes
// from the pure functions in axis.cpp, ticks.cpp, sample.cpp and detail/geometry.h.
#include "plot/plot_draw.h"
#include "plot/detail/geometry.h"

#include <algorithm>
#include <cmath>

namespace plot {

namespace {

using detail::Vec2d;

// Fixed palette: the widget always has a dark background, whatever the ImGui style.
constexpr ImU32 kBackground = IM_COL32(18, 18, 22, 255);
constexpr ImU32 kPlotArea = IM_COL32(26, 27, 33, 255);
constexpr ImU32 kFrame = IM_COL32(255, 255, 255, 90);
constexpr ImU32 kGridMajor = IM_COL32(255, 255, 255, 46);
constexpr ImU32 kGridMinor = IM_COL32(255, 255, 255, 16);
constexpr ImU32 kText = IM_COL32(230, 230, 235, 255);
constexpr ImU32 kTextDim = IM_COL32(160, 160, 172, 255);
constexpr ImU32 kCrosshair = IM_COL32(255, 255, 255, 110);
constexpr ImU32 kLegendBg = IM_COL32(14, 14, 18, 215);
constexpr float kPad = 6.0f;     // outer padding
constexpr float kTickLen = 4.0f; // major tick mark length (minor: half)

// Gap between the data area and the x tick labels: below the tick marks and below the
// lowest y tick label (centred on the bottom edge), so the two never touch in the corner.
float xLabelGap() {
    return std::max(kTickLen + 2.0f, 0.5f * ImGui::GetTextLineHeight() + 1.0f);
}

ImU32 withAlpha(uint32_t color, float factor) {
    const float a = static_cast<float>((color >> 24) & 0xff) * factor;
    return (color & 0x00ffffffu) | (static_cast<ImU32>(std::clamp(a, 0.0f, 255.0f)) << 24);
}

// The data area in pixels and the unit-space ↔ pixel mapping.
struct Frame {
    ImVec2 min, max;
    float w() const { return max.x - min.x; }
    float h() const { return max.y - min.y; }
    ImVec2 toPixel(const Vec2d& u) const {
        return {min.x + static_cast<float>(u.x) * w(), max.y - static_cast<float>(u.y) * h()};
    }
};

// Returns whether the text is wider than [xMin, xMax] (then it is cut at the panel's edge).
// Centred on cx within [xMin, xMax]; too wide, cut with "..." there. True when cut.
bool drawTextCentred(ImDrawList* dl, float cx, float y, float xMin, float xMax, ImU32 col,
                     const std::string& text) {
    if (text.empty()) return false;
    const float w = ImGui::CalcTextSize(text.c_str()).x;
    if (w > xMax - xMin) {
        dl->AddText(ImVec2(xMin, y), col, elided(text, xMax - xMin).c_str());
        return true;
    }
    const float x = std::max(xMin, std::min(cx - 0.5f * w, xMax - w));
    dl->AddText(ImVec2(x, y), col, text.c_str());
    return false;
}

void drawGridAndTicks(ImDrawList* dl, const Frame& f, const std::vector<Tick>& xt,
                      const std::vector<Tick>& yt, const Axis& xa, const Axis& ya) {
    dl->PushClipRect(f.min, f.max, true);
    for (const Tick& t : xt) {
        const float x = f.min.x + static_cast<float>(toUnit(t.value, xa)) * f.w();
        dl->AddLine(ImVec2(x, f.min.y), ImVec2(x, f.max.y), t.major ? kGridMajor : kGridMinor);
    }
    for (const Tick& t : yt) {
        const float y = f.max.y - static_cast<float>(toUnit(t.value, ya)) * f.h();
        dl->AddLine(ImVec2(f.min.x, y), ImVec2(f.max.x, y), t.major ? kGridMajor : kGridMinor);
    }
    dl->PopClipRect();
    for (const Tick& t : xt) {
        const float x = f.min.x + static_cast<float>(toUnit(t.value, xa)) * f.w();
        const float len = t.major ? kTickLen : 0.5f * kTickLen;
        dl->AddLine(ImVec2(x, f.max.y), ImVec2(x, f.max.y + len), kFrame);
    }
    for (const Tick& t : yt) {
        const float y = f.max.y - static_cast<float>(toUnit(t.value, ya)) * f.h();
        const float len = t.major ? kTickLen : 0.5f * kTickLen;
        dl->AddLine(ImVec2(f.min.x - len, y), ImVec2(f.min.x, y), kFrame);
    }
}

// Tick labels, thinned so none overlap (majors win over labelled minors).
void drawTickLabels(ImDrawList* dl, const Frame& f, const std::vector<Tick>& xt,
                    const std::vector<Tick>& yt, const Axis& xa, const Axis& ya, ImVec2 outMin,
                    ImVec2 outMax) {
    const float lineH = ImGui::GetTextLineHeight();
    struct Placed {
        ImVec2 pos;
        const std::string* text;
    };
    auto draw = [&](const std::vector<Placed>& placed, const std::vector<detail::LabelSpan>& spans,
                    double gap) {
        for (size_t i : detail::pickNonOverlapping(spans, gap))
            dl->AddText(placed[i].pos, kText, placed[i].text->c_str());
    };

    std::vector<Placed> placed;
    std::vector<detail::LabelSpan> spans;
    for (const Tick& t : yt) {
        if (t.text.empty()) continue;
        const float w = ImGui::CalcTextSize(t.text.c_str()).x;
        float y = f.max.y - static_cast<float>(toUnit(t.value, ya)) * f.h() - 0.5f * lineH;
        y = std::clamp(y, outMin.y, outMax.y - lineH);
        placed.push_back({ImVec2(f.min.x - kTickLen - 3.0f - w, y), &t.text});
        spans.push_back({y, y + lineH, t.major ? 1 : 0});
    }
    draw(placed, spans, 1.0);

    placed.clear();
    spans.clear();
    const float y = f.max.y + xLabelGap();
    for (const Tick& t : xt) {
        if (t.text.empty()) continue;
        const float w = ImGui::CalcTextSize(t.text.c_str()).x;
        float x = f.min.x + static_cast<float>(toUnit(t.value, xa)) * f.w() - 0.5f * w;
        x = std::clamp(x, outMin.x, outMax.x - w);
        placed.push_back({ImVec2(x, y), &t.text});
        spans.push_back({x, x + w, t.major ? 1 : 0});
    }
    draw(placed, spans, ImGui::CalcTextSize("  ").x);
}

void drawSeries(ImDrawList* dl, const Frame& f, const std::vector<Series>& series, const Axis& xa,
                const Axis& ya) {
    const double marginPx = 8.0;
    const double margin = marginPx / std::max(1.0f, std::min(f.w(), f.h()));
    // Bands first, without anti-aliased fill so neighbouring quads do not show seams.
    const ImDrawListFlags savedFlags = dl->Flags;
    dl->Flags &= ~ImDrawListFlags_AntiAliasedFill;
    std::vector<ImVec2> pts;
    for (const Series& s : series) {
        const ImU32 fill = withAlpha(s.color, 0.25f);
        for (const std::vector<Vec2d>& poly : detail::bandPolygons(s, xa, ya, margin)) {
            pts.clear();
            for (const Vec2d& u : poly)
                pts.push_back(f.toPixel(u));
            dl->AddConvexPolyFilled(pts.data(), static_cast<int>(pts.size()), fill);
        }
    }
    dl->Flags = savedFlags;

    for (const Series& s : series) {
        const float th = std::max(0.5f, s.thickness);
        for (const detail::Polyline& line : detail::curvePolylines(s, xa, ya, margin)) {
            if (line.size() == 1) {
                dl->AddCircleFilled(f.toPixel(line[0]), std::max(1.5f, th), s.color);
                continue;
            }
            std::vector<detail::Polyline> pieces;
            if (s.dashed) {
                detail::Polyline px;
                for (const Vec2d& u : line) {
                    const ImVec2 p = f.toPixel(u);
                    px.push_back({p.x, p.y});
                }
                const double scale = std::max(1.0, static_cast<double>(th) / 1.5);
                pieces = detail::dashPolyline(px, 6.0 * scale, 4.0 * scale);
                for (const detail::Polyline& d : pieces) {
                    pts.clear();
                    for (const Vec2d& p : d)
                        pts.push_back(ImVec2(static_cast<float>(p.x), static_cast<float>(p.y)));
                    dl->AddPolyline(pts.data(), static_cast<int>(pts.size()), s.color,
                                    ImDrawFlags_None, th);
                }
                continue;
            }
            pts.clear();
            for (const Vec2d& u : line)
                pts.push_back(f.toPixel(u));
            dl->AddPolyline(pts.data(), static_cast<int>(pts.size()), s.color, ImDrawFlags_None,
                            th);
        }
    }
}

// Draws the legend; returns the tooltip of the entry under the pointer ("" for none).
std::string drawLegend(ImDrawList* dl, const Frame& f, const std::vector<Series>& series) {
    std::vector<const Series*> shown;
    float textW = 0;
    for (const Series& s : series) {
        if (s.label.empty()) continue;
        shown.push_back(&s);
        textW = std::max(textW, ImGui::CalcTextSize(s.label.c_str()).x);
    }
    if (shown.empty()) return {};
    const float lineH = ImGui::GetTextLineHeight();
    const float swatchW = 2.0f * lineH, gap = 6.0f, rowH = lineH + 2.0f;
    const ImVec2 size(gap + swatchW + gap + textW + gap, gap + rowH * shown.size() + gap - 2.0f);
    const ImVec2 bMax(f.max.x - 8.0f, f.min.y + 8.0f + size.y);
    const ImVec2 bMin(bMax.x - size.x, f.min.y + 8.0f);
    dl->PushClipRect(f.min, f.max, true);
    dl->AddRectFilled(bMin, bMax, kLegendBg, 3.0f);
    dl->AddRect(bMin, bMax, IM_COL32(255, 255, 255, 60), 3.0f);
    std::string tooltip;
    const ImVec2 mouse = ImGui::GetIO().MousePos;
    for (size_t i = 0; i < shown.size(); ++i) {
        const Series& s = *shown[i];
        const float top = bMin.y + gap + rowH * i;
        if (mouse.x >= bMin.x && mouse.x <= bMax.x && mouse.y >= top && mouse.y < top + rowH &&
            ImGui::IsWindowHovered())
            tooltip = s.tooltip;
        const float cy = top + 0.5f * lineH;
        const float x0 = bMin.x + gap, x1 = x0 + swatchW;
        if (s.bandLo.size() >= s.x.size() && s.bandHi.size() >= s.x.size() && !s.x.empty())
            dl->AddRectFilled(ImVec2(x0, cy - 0.35f * lineH), ImVec2(x1, cy + 0.35f * lineH),
                              withAlpha(s.color, 0.25f));
        const float th = std::max(0.5f, s.thickness);
        if (s.dashed) {
            const float d = 0.3f * swatchW;
            for (float x = x0; x < x1 - 1.0f; x += d + 0.2f * swatchW)
                dl->AddLine(ImVec2(x, cy), ImVec2(std::min(x + d, x1), cy), s.color, th);
        } else {
            dl->AddLine(ImVec2(x0, cy), ImVec2(x1, cy), s.color, th);
        }
        if (s.marker) { // error-bar mark: vertical bar with caps and a dot
            const float cx = 0.5f * (x0 + x1), h = 0.4f * lineH, cap = 0.2f * lineH;
            dl->AddLine(ImVec2(cx, cy - h), ImVec2(cx, cy + h), s.color, 1.0f);
            dl->AddLine(ImVec2(cx - cap, cy - h), ImVec2(cx + cap, cy - h), s.color, 1.0f);
            dl->AddLine(ImVec2(cx - cap, cy + h), ImVec2(cx + cap, cy + h), s.color, 1.0f);
            dl->AddCircleFilled(ImVec2(cx, cy), 2.5f, s.color);
        }
        dl->AddText(ImVec2(x1 + gap, top), kText, s.label.c_str());
    }
    dl->PopClipRect();
    return tooltip;
}

void drawHover(ImDrawList* dl, const Frame& f, const PlotState& st, const Axis& xa,
               const Axis& ya) {
    const float x = f.min.x + static_cast<float>(toUnit(st.hoverX, xa)) * f.w();
    dl->PushClipRect(f.min, f.max, true);
    dl->AddLine(ImVec2(x, f.min.y), ImVec2(x, f.max.y), kCrosshair, 1.0f);
    for (const HoverRow& r : st.rows) {
        const double u = toUnit(r.y, ya);
        if (!std::isfinite(u)) continue;
        const ImVec2 p = f.toPixel({toUnit(st.hoverX, xa), u});
        dl->AddCircleFilled(p, 4.0f, IM_COL32(0, 0, 0, 200));
        dl->AddCircleFilled(p, 3.0f, r.color);
    }
    dl->PopClipRect();
}

} // namespace

std::string hoverRowText(const HoverRow& r, size_t index) {
    std::string text = (r.label.empty() ? "series " + std::to_string(index + 1) : r.label) + ": " +
                       (std::isnan(r.y) ? std::string("n/a") : formatValue(r.y));
    if (!std::isnan(r.lo) || !std::isnan(r.hi))
        text += " [" + formatValue(r.lo) + ", " + formatValue(r.hi) + "]";
    return text;
}

namespace {

void drawTooltip(const PlotState& st, const Axis& xa) {
    ImGui::BeginTooltip();
    const std::string xName = xa.label.empty() ? "x" : xa.label;
    ImGui::Text("%s = %s", xName.c_str(), formatValue(st.hoverX).c_str());
    if (!st.rows.empty()) ImGui::Separator();
    for (size_t i = 0; i < st.rows.size(); ++i)
        ImGui::TextColored(ImGui::ColorConvertU32ToFloat4(st.rows[i].color), "%s",
                           hoverRowText(st.rows[i], i).c_str());
    ImGui::EndTooltip();
}

} // namespace

std::string elided(std::string text, float width) {
    if (ImGui::CalcTextSize(text.c_str()).x <= width) return text;
    while (!text.empty() && ImGui::CalcTextSize((text + "...").c_str()).x > width) {
        while (text.size() > 1 && (static_cast<unsigned char>(text.back()) & 0xC0) == 0x80)
            text.pop_back(); // a continuation byte: the whole character goes
        text.pop_back();
    }
    return text + "...";
}

PlotState drawPlot(const char* id, ImVec2 size, const std::vector<Series>& series,
                   const Axis& xAxis, const Axis& yAxis, const std::string& title,
                   const std::string& subtitle, const PlotOptions& options) {
    const ImVec2 avail = ImGui::GetContentRegionAvail();
    if (size.x <= 0) size.x = avail.x;
    if (size.y <= 0) size.y = avail.y;
    size.x = std::max(size.x, 80.0f);
    size.y = std::max(size.y, 60.0f);

    PlotState st;
    st.min = ImGui::GetCursorScreenPos();
    st.max = ImVec2(st.min.x + size.x, st.min.y + size.y);
    ImGui::InvisibleButton(id, size);
    const bool itemHovered = ImGui::IsItemHovered();

    const Axis xa = sanitized(xAxis), ya = sanitized(yAxis);
    ImDrawList* dl = ImGui::GetWindowDrawList();
    const float lineH = ImGui::GetTextLineHeight();

    // Rows: title, subtitle, y-axis label | data area | x tick labels, x-axis label.
    float top = st.min.y + kPad;
    const float titleY = top;
    if (!title.empty()) top += lineH + 2.0f;
    const float subtitleY = top;
    if (!subtitle.empty()) top += lineH + 2.0f;
    const float yLabelY = top;
    top += (ya.label.empty() ? 0.5f : 1.5f) * lineH + 2.0f; // + half the top tick label
    float bottom = st.max.y - kPad;
    const float xLabelY = bottom - lineH;
    if (!xa.label.empty()) bottom -= lineH + 2.0f;
    bottom -= lineH + xLabelGap();
    const float plotH = std::max(8.0f, bottom - top);

    const std::vector<Tick> yt =
        makeTicks(ya, std::max(2, static_cast<int>(plotH / (2.2f * lineH))));
    float yLabelW = 0;
    for (const Tick& t : yt)
        if (!t.text.empty()) yLabelW = std::max(yLabelW, ImGui::CalcTextSize(t.text.c_str()).x);
    const float halfXLabel = 0.5f * ImGui::CalcTextSize("0.000").x;
    Frame f;
    f.min = ImVec2(st.min.x + kPad + yLabelW + kTickLen + 4.0f, top);
    f.max = ImVec2(std::max(f.min.x + 8.0f, st.max.x - kPad - halfXLabel), top + plotH);
    st.plotMin = f.min;
    st.plotMax = f.max;
    const float xLabelSlot = ImGui::CalcTextSize("0.0000").x + 2.0f * lineH;
    const std::vector<Tick> xt = makeTicks(xa, std::max(2, static_cast<int>(f.w() / xLabelSlot)));

    dl->PushClipRect(st.min, st.max, true);
    dl->AddRectFilled(st.min, st.max, kBackground);
    dl->AddRectFilled(f.min, f.max, kPlotArea);
    drawGridAndTicks(dl, f, xt, yt, xa, ya);
    drawSeries(dl, f, series, xa, ya);
    dl->AddRect(f.min, f.max, kFrame);
    drawTickLabels(dl, f, xt, yt, xa, ya, st.min, st.max);

    const float cx = 0.5f * (f.min.x + f.max.x);
    const bool cutTitle =
        drawTextCentred(dl, cx, titleY, st.min.x + kPad, st.max.x - kPad, kText, title);
    const bool cutSubtitle =
        drawTextCentred(dl, cx, subtitleY, st.min.x + kPad, st.max.x - kPad, kTextDim, subtitle);
    // a title cut at a narrow panel's edge is whole in a tooltip
    if ((cutTitle || cutSubtitle) && ImGui::IsWindowHovered()) {
        const ImVec2 m = ImGui::GetIO().MousePos;
        if (m.x >= st.min.x && m.x <= st.max.x && m.y >= titleY && m.y < top)
            ImGui::SetTooltip("%s\n%s", title.c_str(), subtitle.c_str());
    }
    if (!ya.label.empty())
        dl->AddText(ImVec2(st.min.x + kPad, yLabelY), kTextDim, ya.label.c_str());
    drawTextCentred(dl, cx, xLabelY, st.min.x + kPad, st.max.x - kPad, kTextDim, xa.label);
    const std::string legendTip = options.legend ? drawLegend(dl, f, series) : std::string();

    const ImVec2 mouse = ImGui::GetIO().MousePos;
    st.hovered = itemHovered && mouse.x >= f.min.x && mouse.x <= f.max.x && mouse.y >= f.min.y &&
                 mouse.y <= f.max.y;
    if (st.hovered) {
        st.hoverX = fromUnit((mouse.x - f.min.x) / f.w(), xa);
        st.rows = sampleAt(series, st.hoverX);
        if (options.hoverTooltip) drawHover(dl, f, st, xa, ya);
    }
    dl->PopClipRect();
    if (!legendTip.empty())
        ImGui::SetTooltip("%s", legendTip.c_str()); // the legend entry's, not the readout
    else if (st.hovered && options.hoverTooltip)
        drawTooltip(st, xa);
    return st;
}

} // namespace plot
