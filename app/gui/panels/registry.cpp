// The panel registry (registry.h): one entry per panel, in PanelId order.
#include "gui/panels/registry.h"

#include "gui/panels/panels.h"

namespace app {

const std::array<PanelEntry, kPanelCount>& panelRegistry() {
    static const std::array<PanelEntry, kPanelCount> kPanels = {{
        {PanelId::Models, "Models", "Models", 0, Area::LeftTop, true, false,
         [](Workbench& wb, UiState& ui) { drawModelsPanel(wb, ui.shared); }},
        {PanelId::Parameters, "Parameters", "Parameters", 0, Area::LeftBottom, true, false,
         [](Workbench& wb, UiState& ui) { drawParametersPanel(wb, ui.parameters, ui.shared); }},
        {PanelId::Render, "Render", "Render", 1, Area::Centre, true, true,
         [](Workbench& wb, UiState& ui) { drawRenderPanel(wb, ui.render, ui.shared); }},
        {PanelId::Pencil, "Pencil plot", "PencilPlot", 1, Area::Centre, true, false,
         [](Workbench& wb, UiState& ui) { drawPencilPanel(wb, ui.pencil, ui.shared); }},
        {PanelId::LitSpheres, "Lit spheres", "LitSpheres", 1, Area::Centre, true, false,
         [](Workbench& wb, UiState& ui) { drawLitSpherePanel(wb, ui.litSpheres, ui.shared); }},
        {PanelId::PointCloud, "Point cloud", "PointCloud", 1, Area::Centre, true, true,
         [](Workbench& wb, UiState& ui) { drawPointCloudPanel(wb, ui.pointCloud, ui.shared); }},
        {PanelId::Octree, "Octree", "Octree", 1, Area::Centre, true, true,
         [](Workbench& wb, UiState& ui) { drawOctreePanel(wb, ui.octree, ui.shared); }},
        {PanelId::Irradiance, "Irradiance", "Irradiance", 1, Area::Centre, true, true,
         [](Workbench& wb, UiState& ui) { drawIrradiancePanel(wb, ui.irradiance, ui.shared); }},
        {PanelId::Traversal, "Traversal debugger", "Traversal", 2, Area::Right, true, false,
         [](Workbench& wb, UiState& ui) { drawTraversalPanel(wb, ui.traversal, ui.shared); }},
        {PanelId::Captures, "Captures", "Captures", 1, Area::Centre, true, false,
         [](Workbench& wb, UiState& ui) { drawCapturesPanel(wb, ui.captures, ui.shared); }},
        {PanelId::Slice, "BSSRDF slice", "Slice", 1, Area::Centre, true, false,
         [](Workbench& wb, UiState& ui) { drawSlicePanel(wb, ui.slice, ui.shared); }},
        {PanelId::Scoreboard, "Scoreboard", "Scoreboard", 1, Area::Centre, true, false,
         [](Workbench& wb, UiState& ui) { drawScoreboardPanel(wb, ui.scoreboard, ui.shared); }},
        {PanelId::Fit, "Fit", "Fit", 1, Area::Centre, false, false,
         [](Workbench& wb, UiState& ui) { drawFitPanel(wb, ui.fit, ui.shared); }},
        {PanelId::Errors, "Errors", "Errors", 3, Area::Bottom, true, false,
         [](Workbench& wb, UiState& ui) { drawErrorsPanel(wb, ui.errors, ui.shared); }},
        {PanelId::Log, "Log", "Log", 3, Area::Bottom, true, false,
         [](Workbench& wb, UiState& ui) { drawLogPanel(wb, ui.errors, ui.shared); }},
        {PanelId::Timings, "Timings", "Timings", 3, Area::Bottom, true, false,
         [](Workbench& wb, UiState& ui) { drawTimingsPanel(wb, ui.shared); }},
    }};
    return kPanels;
}

const PanelEntry& panelEntry(PanelId id) {
    return panelRegistry()[static_cast<size_t>(id)];
}

UiState::UiState() {
    for (const PanelEntry& p : panelRegistry())
        shared.isOpen(p.id) = p.defaultOpen;
}

} // namespace app
