// The workspace layout: the window tiled into areas — a left column (two areas stacked, for
// Models and Parameters), a centre area with the stage views as tabs, a right inspector and a
// bottom strip — separated by draggable splitters; any panel may float out as its own window
// and dock back. ImGui 1.86 (Debian 12) has no docking branch, so the tiling is written here:
// this file is its geometry and saved state only (no ImGui), so it is tested on its own; the
// drawing is gui/workspace.cpp.
#pragma once

#include <array>
#include <cstddef>
#include <string>

namespace app {

enum class Area { LeftTop, LeftBottom, Centre, Right, Bottom, Count };
constexpr size_t kAreaCount = static_cast<size_t>(Area::Count);
const char* areaName(Area a); // "left-top", "centre", ... (saved state, window names)

struct Rect {
    float x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    float width() const { return x1 - x0; }
    float height() const { return y1 - y0; }
    bool contains(const Rect& r, float slack = 0.5f) const {
        return r.x0 >= x0 - slack && r.y0 >= y0 - slack && r.x1 <= x1 + slack && r.y1 <= y1 + slack;
    }
    bool overlaps(const Rect& r, float slack = 0.5f) const {
        return r.x0 < x1 - slack && x0 < r.x1 - slack && r.y0 < y1 - slack && y0 < r.y1 - slack;
    }
};

// The splitters, each moving one of WorkspaceSplits' fractions.
enum class Splitter { Left, Right, Bottom, LeftColumn, Count };
// An area's or splitter's index into the layout's arrays.
inline size_t idx(Area a) {
    return static_cast<size_t>(a);
}
inline size_t idx(Splitter s) {
    return static_cast<size_t>(s);
}
constexpr size_t kSplitterCount = static_cast<size_t>(Splitter::Count);

// Where the splitters are, as fractions of the space they divide (saved, View → Reset layout
// restores these defaults).
struct WorkspaceSplits {
    float left = 0.25f;       // left column width / window width
    float right = 0.24f;      // right inspector width / window width
    float bottom = 0.22f;     // bottom strip height / height below the menu bar
    float leftColumn = 0.36f; // top area's share of the left column
};

// Smallest sizes an area keeps while the window allows it (pixels).
struct WorkspaceLimits {
    float gap = 6;          // splitter thickness between areas
    float minSide = 200;    // left column and right inspector width
    float minCentre = 260;  // centre width
    float minBottom = 80;   // bottom strip height
    float minMain = 180;    // height above the bottom strip
    float minStacked = 100; // each of the two left areas
};

struct WorkspaceRects {
    std::array<Rect, kAreaCount> area{};
    std::array<bool, kAreaCount> present{}; // an area without docked panels takes no space
    std::array<Rect, kSplitterCount> splitter{};
    std::array<bool, kSplitterCount> splitterPresent{};
};

// Tiles `view` (the window below the menu bar) for the areas that hold docked panels. Every
// present area lies inside `view`, no two overlap, and the splitters sit in the gaps between
// them; fractions outside what the limits allow are clamped (the saved fractions are not).
WorkspaceRects tileWorkspace(const Rect& view, const WorkspaceSplits& splits,
                             const std::array<bool, kAreaCount>& occupied,
                             const WorkspaceLimits& limits = {});

// Moves a splitter by `delta` pixels (x for the vertical ones, y for Bottom/LeftColumn),
// updating its fraction; the result is clamped to [0.05, 0.95].
void dragSplitter(WorkspaceSplits& splits, Splitter s, float delta, const Rect& view,
                  const WorkspaceRects& current);

// Where a floating window goes: its saved rectangle, moved and shrunk as little as possible to
// lie inside `view` (a window that was saved on a larger screen stays reachable).
Rect clampInto(const Rect& r, const Rect& view);

} // namespace app
