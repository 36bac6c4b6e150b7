// The panel registry: every panel of the workbench, once — its window title (also its View
// menu label), the key its visibility is saved under, its View-menu group, whether it is open
// by default, whether it needs the scene pipeline, and the function that draws it with its own
// state. The menu bar, the frame loop and the saved layout all read this table: adding a panel
// is one draw function and one entry here (docs/ARCHITECTURE.md, "How to add a panel").
#pragma once

#include "gui/ui_state.h"
#include "pipeline/workbench.h"

#include <array>

namespace app {

struct PanelEntry {
    PanelId id;
    const char* title;  // window title and View-menu label
    const char* iniKey; // visibility key in the saved layout
    int menuGroup;      // View menu: a separator between groups
    Area area;          // where it docks in the workspace
    bool defaultOpen;
    bool needsScene; // the scene pipeline runs while a panel with this flag is open (the
                     // Traversal debugger has none: it shows the trace of a pixel clicked in
                     // the Render panel, so it can stay open without keeping the scene running)
    void (*draw)(Workbench& wb, UiState& ui);
};

// In PanelId order.
const std::array<PanelEntry, kPanelCount>& panelRegistry();
const PanelEntry& panelEntry(PanelId id);

} // namespace app
