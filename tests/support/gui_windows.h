// Shared by GUI tests: what ImGui drew in the last frame, read from its window list.
#pragma once

#include "gui/gui.h"
#include "gui/panels/registry.h"
#include "gui/workspace_layout.h"
#include "pipeline/scene_stage.h"
#include "small_scene.h"

#include <GLFW/glfw3.h>
#include <gtest/gtest.h>
#include <imgui.h>
#include <imgui_internal.h>

#include <string>
#include <vector>

namespace testsupport {

// The top-level windows drawn in the last frame (no children, tooltips, popups, menus).
inline std::vector<ImGuiWindow*> topWindows() {
    std::vector<ImGuiWindow*> out;
    for (ImGuiWindow* w : ImGui::GetCurrentContext()->Windows) {
        if (!w->Active || w->Hidden) continue;
        if (w->Flags & (ImGuiWindowFlags_ChildWindow | ImGuiWindowFlags_Tooltip |
                        ImGuiWindowFlags_Popup | ImGuiWindowFlags_ChildMenu))
            continue;
        out.push_back(w);
    }
    return out;
}

inline app::Rect rectOf(const ImGuiWindow* w) {
    return {w->Pos.x, w->Pos.y, w->Pos.x + w->Size.x, w->Pos.y + w->Size.y};
}

// The child window a panel draws into (workspace.cpp), when it was drawn in the last frame.
inline ImGuiWindow* panelWindow(app::PanelId id) {
    const std::string key = std::string("/") + app::panelEntry(id).iniKey + "_";
    for (ImGuiWindow* w : ImGui::GetCurrentContext()->Windows) {
        if (!(w->Flags & ImGuiWindowFlags_ChildWindow) || !w->Active) continue;
        if (std::string(w->Name).find(key) != std::string::npos) return w;
    }
    return nullptr;
}

// Every table panel `id` drew in the last frame shows its cells whole: no cell's content runs
// past its column's right edge, where the table clips it (a cut "0.804 +- 0.00" reads as a
// different number). Returns how many tables were checked.
inline int expectTablesShowTheirCells(app::PanelId id) {
    const ImGuiWindow* panel = panelWindow(id);
    if (!panel) {
        ADD_FAILURE() << app::panelEntry(id).title << " was not drawn";
        return 0;
    }
    ImGuiContext& g = *ImGui::GetCurrentContext();
    int checked = 0;
    for (int n = 0; n < g.Tables.GetMapSize(); ++n) {
        const ImGuiTable* t = g.Tables.TryGetMapData(n);
        if (!t || t->LastFrameActive < g.FrameCount - 1) continue;
        const ImGuiWindow* w = t->OuterWindow;
        while (w && w != panel)
            w = w->ParentWindow;
        if (!w) continue;
        ++checked;
        for (int c = 0; c < t->ColumnsCount; ++c) {
            const ImGuiTableColumn& col = t->Columns[c];
            EXPECT_LE(col.ContentMaxXUnfrozen, col.MaxX + 0.5f)
                << app::panelEntry(id).title << ": table column " << c << " is "
                << col.MaxX - col.MinX << " wide, its widest cell "
                << col.ContentMaxXUnfrozen - col.MinX;
        }
    }
    return checked;
}

// The panel's controls and text fit its width: nothing runs past the right edge, so the panel
// never scrolls sideways (ImGui's horizontal scroll range, read two frames after the panel came
// to the front: the first frame lays out without knowing whether a vertical scrollbar follows,
// the second lays out with it, the third reads the second's width). And the layout holds
// still: over the next frames the vertical scrollbar does not come and go (an image sized by
// the space beside a scrollbar made the Render panel flip between two layouts every frame at
// some sizes). Content may grow while work runs, so one change is allowed, not a flip back.
// Its tables show their cells whole (expectTablesShowTheirCells).
inline void expectFitsItsWidth(app::HeadlessGui& gui, app::PanelId id) {
    const char* title = app::panelEntry(id).title;
    gui.frame();
    gui.frame();
    gui.frame();
    const ImGuiWindow* pw = panelWindow(id);
    ASSERT_NE(pw, nullptr) << title;
    EXPECT_EQ(pw->ScrollMax.x, 0.0f) << title << ": content " << pw->ContentSize.x << " px wide, "
                                     << pw->InnerRect.GetWidth() << " px shown";
    std::string scrollbar(1, pw->ScrollbarY ? '|' : '.');
    for (int i = 0; i < 3; ++i) {
        gui.frame();
        pw = panelWindow(id);
        ASSERT_NE(pw, nullptr) << title;
        scrollbar += pw->ScrollbarY ? '|' : '.';
    }
    int changes = 0;
    for (size_t i = 1; i < scrollbar.size(); ++i)
        changes += scrollbar[i] != scrollbar[i - 1];
    EXPECT_LE(changes, 1) << title << ": the vertical scrollbar comes and goes over four frames ("
                          << scrollbar << ")";
    expectTablesShowTheirCells(id);
}

// A real click at (x, y), or at the centre of `r`: the pointer arrives, presses, releases and
// leaves, a frame each (ImGui sees hover, press and release as a user's click).
inline void clickAt(app::HeadlessGui& gui, float x, float y) {
    gui.mouse(x, y, false);
    gui.frame();
    gui.mouse(x, y, true);
    gui.frame();
    gui.mouse(x, y, false);
    gui.frame();
    gui.noMouse();
    gui.frame();
}
inline void click(app::HeadlessGui& gui, const app::Rect& r) {
    clickAt(gui, 0.5f * (r.x0 + r.x1), 0.5f * (r.y0 + r.y1));
}

// The keyboard of a dialog: Enter and Escape mapped as the GLFW backend maps them; text typed
// in one frame; a key pressed in one frame and released in the next; the popups open (a modal
// dialog is one).
inline void mapDialogKeys() {
    ImGuiIO& io = ImGui::GetIO();
    io.KeyMap[ImGuiKey_Enter] = GLFW_KEY_ENTER;
    io.KeyMap[ImGuiKey_Escape] = GLFW_KEY_ESCAPE;
}
inline void typeText(app::HeadlessGui& gui, const std::string& text) {
    ImGui::GetIO().AddInputCharactersUTF8(text.c_str());
    gui.frame();
}
inline void pressKey(app::HeadlessGui& gui, int key) {
    ImGui::GetIO().KeysDown[key] = true;
    gui.frame();
    ImGui::GetIO().KeysDown[key] = false;
    gui.frame();
}
inline int openPopups() {
    return ImGui::GetCurrentContext()->OpenPopupStack.Size;
}

// The text panel `id` draws in the next frame (UiState::recordText): what a user reads there,
// for tests of what a panel says; every run of spaces and line breaks one space (a wrapped
// sentence reads as one line).
inline std::string panelText(app::HeadlessGui& gui, app::PanelId id) {
    gui.ui().recordText = true;
    gui.ui().panelText.erase(id);
    gui.frame();
    gui.ui().recordText = false;
    const auto it = gui.ui().panelText.find(id);
    std::string text;
    if (it != gui.ui().panelText.end())
        for (const char c : it->second) {
            const bool space = c == ' ' || c == '\n' || c == '\r' || c == '\t';
            if (!space)
                text += c;
            else if (!text.empty() && text.back() != ' ')
                text += ' ';
        }
    return text;
}

} // namespace testsupport
