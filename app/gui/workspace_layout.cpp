// Workspace geometry (workspace_layout.h): the tiling of the window into areas and splitters.
#include "gui/workspace_layout.h"

#include <algorithm>

namespace app {

const char* areaName(Area a) {
    switch (a) {
    case Area::LeftTop:
        return "left-top";
    case Area::LeftBottom:
        return "left-bottom";
    case Area::Centre:
        return "centre";
    case Area::Right:
        return "right";
    case Area::Bottom:
        return "bottom";
    case Area::Count:
        break;
    }
    return "?";
}

namespace {

// A size of `fraction · total` kept within [lo, hi]; when the window is too small for both
// limits, the upper one wins so the neighbours keep their minimum first.
float sized(float fraction, float total, float lo, float hi) {
    return std::max(0.0f, std::min(std::max(fraction * total, lo), hi));
}

} // namespace

WorkspaceRects tileWorkspace(const Rect& view, const WorkspaceSplits& splits,
                             const std::array<bool, kAreaCount>& occupied,
                             const WorkspaceLimits& limits) {
    WorkspaceRects out;
    WorkspaceLimits lim = limits;
    const bool left = occupied[idx(Area::LeftTop)] || occupied[idx(Area::LeftBottom)];
    const bool right = occupied[idx(Area::Right)];
    const bool bottom = occupied[idx(Area::Bottom)];
    const float W = view.width(), H = view.height();

    // A window smaller than the minimums together shrinks them in proportion.
    const float gaps = lim.gap * float(int(left) + int(right));
    const float needW = lim.minCentre + lim.minSide * float(int(left) + int(right));
    if (W - gaps < needW) {
        const float k = std::max(0.0f, W - gaps) / needW;
        lim.minCentre *= k;
        lim.minSide *= k;
    }
    const float needH = std::max(lim.minMain + (bottom ? lim.minBottom + lim.gap : 0.0f),
                                 2 * lim.minStacked + lim.gap);
    if (H < needH) {
        const float k = std::max(0.0f, H - lim.gap) / (needH - lim.gap);
        lim.minMain *= k;
        lim.minBottom *= k;
        lim.minStacked *= k;
    }
    // Columns: left | centre | right, each gap holding a vertical splitter.
    float wl = 0, wr = 0;
    if (right)
        wr = sized(splits.right, W, lim.minSide,
                   W - gaps - lim.minCentre - (left ? lim.minSide : 0.0f));
    if (left) wl = sized(splits.left, W, lim.minSide, W - gaps - lim.minCentre - wr);
    const float xl = view.x0 + wl;                   // left column's right edge
    const float xc0 = left ? xl + lim.gap : view.x0; // centre's left edge
    const float xc1 = right ? view.x1 - wr - lim.gap : view.x1;
    // Rows of the centre and right: main | bottom strip.
    float hb = 0;
    if (bottom) hb = sized(splits.bottom, H, lim.minBottom, H - lim.gap - lim.minMain);
    const float yb = bottom ? view.y1 - hb : view.y1; // bottom strip's top edge
    const float ym = bottom ? yb - lim.gap : view.y1; // main row's bottom edge

    if (left) {
        // The left column runs the full height; its two areas stack.
        const bool top = occupied[idx(Area::LeftTop)], low = occupied[idx(Area::LeftBottom)];
        if (top && low) {
            const float ht =
                sized(splits.leftColumn, H, lim.minStacked, H - lim.gap - lim.minStacked);
            out.area[idx(Area::LeftTop)] = {view.x0, view.y0, xl, view.y0 + ht};
            out.area[idx(Area::LeftBottom)] = {view.x0, view.y0 + ht + lim.gap, xl, view.y1};
            out.splitter[idx(Splitter::LeftColumn)] = {view.x0, view.y0 + ht, xl,
                                                       view.y0 + ht + lim.gap};
            out.splitterPresent[idx(Splitter::LeftColumn)] = true;
        } else {
            out.area[idx(top ? Area::LeftTop : Area::LeftBottom)] = {view.x0, view.y0, xl, view.y1};
        }
        out.present[idx(Area::LeftTop)] = top;
        out.present[idx(Area::LeftBottom)] = low;
        out.splitter[idx(Splitter::Left)] = {xl, view.y0, xc0, view.y1};
        out.splitterPresent[idx(Splitter::Left)] = true;
    }
    out.area[idx(Area::Centre)] = {xc0, view.y0, xc1, ym};
    out.present[idx(Area::Centre)] = true; // the centre always shows (empty: a hint)
    if (right) {
        out.area[idx(Area::Right)] = {xc1 + lim.gap, view.y0, view.x1, ym};
        out.present[idx(Area::Right)] = true;
        out.splitter[idx(Splitter::Right)] = {xc1, view.y0, xc1 + lim.gap, ym};
        out.splitterPresent[idx(Splitter::Right)] = true;
    }
    if (bottom) {
        out.area[idx(Area::Bottom)] = {xc0, yb, view.x1, view.y1};
        out.present[idx(Area::Bottom)] = true;
        out.splitter[idx(Splitter::Bottom)] = {xc0, ym, view.x1, yb};
        out.splitterPresent[idx(Splitter::Bottom)] = true;
    }
    return out;
}

void dragSplitter(WorkspaceSplits& splits, Splitter s, float delta, const Rect& view,
                  const WorkspaceRects& cur) {
    const float W = std::max(1.0f, view.width()), H = std::max(1.0f, view.height());
    auto clamp = [](float f) { return std::clamp(f, 0.05f, 0.95f); };
    switch (s) {
    case Splitter::Left:
        splits.left = clamp((cur.area[idx(Area::LeftTop)].width() > 0
                                 ? cur.area[idx(Area::LeftTop)].width()
                                 : cur.area[idx(Area::LeftBottom)].width()) /
                                W +
                            delta / W);
        break;
    case Splitter::Right:
        splits.right = clamp(cur.area[idx(Area::Right)].width() / W - delta / W);
        break;
    case Splitter::Bottom:
        splits.bottom = clamp(cur.area[idx(Area::Bottom)].height() / H - delta / H);
        break;
    case Splitter::LeftColumn:
        splits.leftColumn = clamp(cur.area[idx(Area::LeftTop)].height() / H + delta / H);
        break;
    case Splitter::Count:
        break;
    }
}

Rect clampInto(const Rect& r, const Rect& view) {
    const float w = std::min(std::max(r.width(), 120.0f), view.width());
    const float h = std::min(std::max(r.height(), 80.0f), view.height());
    const float x0 = std::clamp(r.x0, view.x0, view.x1 - w);
    const float y0 = std::clamp(r.y0, view.y0, view.y1 - h);
    return {x0, y0, x0 + w, y0 + h};
}

} // namespace app
