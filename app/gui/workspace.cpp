// The workspace (workspace_layout.h) drawn with ImGui: one opaque, fixed host window per area with
// a tab bar of its docked panels, splitter strips between areas, and a window per floating panel.
// A tab's context menu (right click) and the "float" button float a panel out; a floating
// window's "Dock" button (or View → Float) docks it back. Closing a tab closes the panel (the
// View menu reopens it).
#include "gui/panels/panels.h"
#include "gui/panels/registry.h"

#include <imgui.h>
#include <imgui_internal.h>

#include <algorithm>
#include <string>

namespace app {
namespace {

constexpr ImGuiWindowFlags kHostFlags =
    ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoMove |
    ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoSavedSettings |
    ImGuiWindowFlags_NoBringToFrontOnFocus | ImGuiWindowFlags_NoScrollbar |
    ImGuiWindowFlags_NoScrollWithMouse | ImGuiWindowFlags_NoFocusOnAppearing;

bool docked(const UiShared& ui, const PanelEntry& p) {
    return ui.open[static_cast<size_t>(p.id)] && !ui.workspace.floating[static_cast<size_t>(p.id)];
}

// The label of a panel's tab or window: the Errors panel counts its problems; the part after
// ### keeps the ID stable while the count changes.
std::string panelLabel(Workbench& wb, const PanelEntry& p) {
    std::string label = p.title;
    if (p.id == PanelId::Errors) {
        const size_t n = wb.errors().size();
        if (n > 0) label += " (" + std::to_string(n) + ")";
    }
    return label + "###" + p.iniKey;
}

Rect viewRect() {
    const ImGuiViewport* vp = ImGui::GetMainViewport();
    // The menu bar's height is taken off explicitly: on the first frame the viewport's work
    // area does not know it yet.
    const float menu = ImGui::GetFrameHeight();
    return {vp->Pos.x, vp->Pos.y + menu, vp->Pos.x + vp->Size.x, vp->Pos.y + vp->Size.y};
}

// A floating window's first place: centred, half the width and 60 % of the height.
Rect defaultFloatRect(const Rect& view) {
    const float w = view.width() * 0.5f, h = view.height() * 0.6f;
    const float x0 = view.x0 + (view.width() - w) * 0.5f;
    const float y0 = view.y0 + (view.height() - h) * 0.5f;
    return {x0, y0, x0 + w, y0 + h};
}

void floatOut(UiShared& ui, const PanelEntry& p) {
    ui.workspace.floating[static_cast<size_t>(p.id)] = true;
    ui.show(p.id);
}

void drawPanelBody(Workbench& wb, UiState& ui, const PanelEntry& p) {
    // A child window per panel: its own scrolling, and the panel's widgets keep their IDs
    // wherever it is shown.
    ImGui::BeginChild(p.iniKey, ImVec2(0, 0), false, ImGuiWindowFlags_HorizontalScrollbar);
    // ImGui widens a sideways-scrolling window's work area to its content, and full-width
    // items (tab bars, tables, separators, negative widths) measure from that area: a row that
    // ran over once, e.g. on the frame before the vertical scrollbar appeared, would keep the
    // panel scrolling sideways for good. The work area is what the panel shows; an item wider
    // than that still scrolls into view.
    ImGuiWindow* w = ImGui::GetCurrentWindow();
    const float shown =
        w->InnerRect.GetWidth() - 2 * std::max(w->WindowPadding.x, w->WindowBorderSize);
    w->WorkRect.Max.x = std::min(w->WorkRect.Max.x, w->WorkRect.Min.x + shown);
    w->ContentRegionRect.Max.x = std::min(w->ContentRegionRect.Max.x, w->WorkRect.Max.x);
    // Widgets without their own width leave room for a label of about 15 characters, or 45 %
    // of a narrow area (labels there are short: units go into the value's format).
    const float avail = ImGui::GetContentRegionAvail().x;
    ImGui::PushItemWidth(-std::min(ImGui::GetFontSize() * 9.5f, avail * 0.45f));
    if (ui.recordText) ImGui::LogToBuffer(0); // 0: no tree node opened for the log
    p.draw(wb, ui);
    if (ui.recordText) {
        ImGuiContext& g = *ImGui::GetCurrentContext();
        ui.panelText[p.id] = g.LogEnabled ? g.LogBuffer.c_str() : "";
        ImGui::LogFinish();
    }
    ImGui::PopItemWidth();
    ImGui::EndChild();
}

void drawArea(Workbench& wb, UiState& ui, Area area, const Rect& r, int want) {
    UiShared& sh = ui.shared;
    const std::string name = std::string("##area.") + areaName(area);
    ImGui::SetNextWindowPos(ImVec2(r.x0, r.y0));
    ImGui::SetNextWindowSize(ImVec2(r.width(), r.height()));
    ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(4, 4));
    ImGui::Begin(name.c_str(), nullptr, kHostFlags);
    ImGui::PopStyleVar();
    int& selected = sh.workspace.selected[idx(area)];
    const PanelEntry* floatRequest = nullptr;
    bool any = false;
    // Tabs that do not fit scroll, with working arrows and a list button ("v") that reaches
    // every tab at any width.
    if (ImGui::BeginTabBar("tabs", ImGuiTabBarFlags_FittingPolicyScroll |
                                       ImGuiTabBarFlags_TabListPopupButton)) {
        // The workspace's choice (`want`) is the authority; ImGui's tab bar follows it in this
        // frame (a SetSelected flag would act a frame late; a tab submitted for the first
        // time still shows a frame late). A click on a tab is the user's new choice, and so is
        // a tab the bar's arrows or list chose during its layout (it sets SelectedTabId itself).
        ImGuiTabBar* bar = ImGui::GetCurrentContext()->CurrentTabBar;
        ImGuiID setId = 0;
        bool wantKnown = want < 0; // the wanted tab exists in the bar (not submitted first now)
        // the bar's width: when it changes, the selected tab is scrolled into view again
        float& lastWidth = *ImGui::GetStateStorage()->GetFloatRef(ImGui::GetID("##barWidth"), 0);
        const bool resized = lastWidth != bar->BarRect.GetWidth();
        lastWidth = bar->BarRect.GetWidth();
        if (want >= 0) {
            const ImGuiID wantId = ImGui::GetCurrentWindow()->GetIDNoKeepAlive(
                panelLabel(wb, panelEntry(static_cast<PanelId>(want))).c_str());
            wantKnown = ImGui::TabBarFindTabByID(bar, wantId) != nullptr;
            if (bar->SelectedTabId != wantId || resized) bar->NextSelectedTabId = setId = wantId;
        }
        selected = want;
        const ImGuiID expected = setId ? setId : bar->SelectedTabId;
        for (const PanelEntry& p : panelRegistry()) {
            if (p.area != area || !docked(sh, p)) continue;
            any = true;
            bool open = true;
            const std::string label = panelLabel(wb, p);
            const bool shown = ImGui::BeginTabItem(label.c_str(), &open);
            if (ImGui::BeginPopupContextItem()) {
                if (ImGui::MenuItem("Float out")) floatRequest = &p;
                if (ImGui::MenuItem("Close")) open = false;
                ImGui::EndPopup();
            }
            if (shown) {
                drawPanelBody(wb, ui, p);
                ImGui::EndTabItem();
            }
            const ImGuiID id = ImGui::GetCurrentWindow()->GetIDNoKeepAlive(label.c_str());
            if (bar->NextSelectedTabId != 0 && bar->NextSelectedTabId != setId &&
                bar->NextSelectedTabId == id)
                selected = static_cast<int>(p.id); // clicked
            else if (wantKnown && bar->SelectedTabId != expected && bar->SelectedTabId == id)
                selected = static_cast<int>(p.id); // the arrows or the tab list chose it
            if (!open) sh.isOpen(p.id) = false;
        }
        if (any && selected >= 0 &&
            ImGui::TabItemButton("^", ImGuiTabItemFlags_Trailing | ImGuiTabItemFlags_NoTooltip))
            floatRequest = &panelEntry(static_cast<PanelId>(selected));
        if (any && ImGui::IsItemHovered())
            ImGui::SetTooltip("float the shown panel out (or right click a tab)");
        ImGui::EndTabBar();
    }
    if (!any) ImGui::TextDisabled("No panel here: open one from the View menu.");
    ImGui::End();
    if (floatRequest) floatOut(sh, *floatRequest);
}

// A splitter strip: dragging moves the boundary (workspace_layout.h, dragSplitter).
void drawSplitter(WorkspaceState& ws, Splitter s, const WorkspaceRects& rects, const Rect& view) {
    const Rect& r = rects.splitter[static_cast<size_t>(s)];
    const bool vertical = s == Splitter::Left || s == Splitter::Right;
    const std::string name = "##split." + std::to_string(static_cast<int>(s));
    ImGui::SetNextWindowPos(ImVec2(r.x0, r.y0));
    ImGui::SetNextWindowSize(ImVec2(r.width(), r.height()));
    ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(0, 0));
    ImGui::PushStyleVar(ImGuiStyleVar_WindowMinSize, ImVec2(1, 1));
    ImGui::Begin(name.c_str(), nullptr,
                 kHostFlags | ImGuiWindowFlags_NoBackground | ImGuiWindowFlags_NoDecoration);
    ImGui::PopStyleVar(2);
    ImGui::InvisibleButton("##drag", ImVec2(std::max(1.0f, r.width()), std::max(1.0f, r.height())));
    if (ImGui::IsItemHovered() || ImGui::IsItemActive()) {
        ImGui::SetMouseCursor(vertical ? ImGuiMouseCursor_ResizeEW : ImGuiMouseCursor_ResizeNS);
        ImGui::GetWindowDrawList()->AddRectFilled(ImVec2(r.x0, r.y0), ImVec2(r.x1, r.y1),
                                                  ImGui::GetColorU32(ImGuiCol_SeparatorHovered));
    }
    if (ImGui::IsItemActive()) {
        const ImVec2 d = ImGui::GetIO().MouseDelta;
        const float delta = vertical ? d.x : d.y;
        if (delta != 0) dragSplitter(ws.splits, s, delta, view, rects);
    }
    ImGui::End();
}

void drawFloating(Workbench& wb, UiState& ui, const PanelEntry& p, const Rect& view, int request) {
    UiShared& sh = ui.shared;
    const size_t i = static_cast<size_t>(p.id);
    Rect& saved = sh.workspace.floatRect[i];
    if (saved.width() <= 0) saved = defaultFloatRect(view);
    const Rect want = clampInto(saved, view);
    // Placed on first show, and moved back in whenever the window (or the OS window) shrank
    // so that it would leave the viewport; otherwise the user's moves and resizes stand.
    const bool place = !sh.workspace.placed[i] || want.x0 != saved.x0 || want.y0 != saved.y0 ||
                       want.x1 != saved.x1 || want.y1 != saved.y1;
    if (place) {
        ImGui::SetNextWindowPos(ImVec2(want.x0, want.y0));
        ImGui::SetNextWindowSize(ImVec2(want.width(), want.height()));
        sh.workspace.placed[i] = true;
    }
    if (request == static_cast<int>(p.id)) ImGui::SetNextWindowFocus();
    bool open = true;
    const bool shown = ImGui::Begin(panelLabel(wb, p).c_str(), &open,
                                    ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoCollapse |
                                        ImGuiWindowFlags_NoFocusOnAppearing);
    const ImVec2 pos = ImGui::GetWindowPos(), size = ImGui::GetWindowSize();
    saved = clampInto({pos.x, pos.y, pos.x + size.x, pos.y + size.y}, view);
    bool dock = false;
    if (shown) {
        dock = ImGui::SmallButton("Dock");
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("put it back as a tab of its area");
        drawPanelBody(wb, ui, p);
    }
    ImGui::End();
    if (!open) sh.isOpen(p.id) = false;
    if (!open || dock) sh.workspace.placed[i] = false;
    if (dock) {
        sh.workspace.floating[i] = false;
        sh.show(p.id);
    }
}

} // namespace

std::array<bool, kPanelCount> shownPanels(const UiShared& ui) {
    std::array<bool, kPanelCount> shown{};
    for (size_t a = 0; a < kAreaCount; ++a) {
        int pick = -1, first = -1;
        for (const PanelEntry& p : panelRegistry()) {
            if (static_cast<size_t>(p.area) != a || !docked(ui, p)) continue;
            const int id = static_cast<int>(p.id);
            if (first < 0) first = id;
            if (id == ui.showRequest || (id == ui.workspace.selected[a] && pick < 0)) pick = id;
        }
        if (pick < 0) pick = first;
        if (pick >= 0) shown[static_cast<size_t>(pick)] = true;
    }
    for (const PanelEntry& p : panelRegistry()) {
        const size_t i = static_cast<size_t>(p.id);
        if (ui.open[i] && ui.workspace.floating[i]) shown[i] = true;
    }
    return shown;
}

void drawWorkspace(Workbench& wb, UiState& ui) {
    UiShared& sh = ui.shared;
    const Rect view = viewRect();
    // What each area shows is decided before drawing (shownPanels), so the scene pipeline
    // follows the visible panels in this very frame.
    const auto shown = shownPanels(sh);
    std::array<int, kAreaCount> want;
    want.fill(-1);
    std::array<bool, kAreaCount> occupied{};
    for (const PanelEntry& p : panelRegistry()) {
        if (!docked(sh, p)) continue;
        occupied[idx(p.area)] = true;
        if (shown[static_cast<size_t>(p.id)]) want[idx(p.area)] = static_cast<int>(p.id);
    }
    const WorkspaceRects rects = tileWorkspace(view, sh.workspace.splits, occupied);
    const int request = sh.showRequest;
    sh.showRequest = -1; // a request raised while drawing is served in the next frame
    for (size_t a = 0; a < kAreaCount; ++a)
        if (rects.present[a]) drawArea(wb, ui, static_cast<Area>(a), rects.area[a], want[a]);
    for (size_t s = 0; s < kSplitterCount; ++s)
        if (rects.splitterPresent[s])
            drawSplitter(sh.workspace, static_cast<Splitter>(s), rects, view);
    for (const PanelEntry& p : panelRegistry()) {
        const size_t i = static_cast<size_t>(p.id);
        if (sh.open[i] && sh.workspace.floating[i]) drawFloating(wb, ui, p, view, request);
    }
}

} // namespace app
