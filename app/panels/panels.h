// One function per panel: each only shows and edits Workbench / UiState; no algorithms.
#pragma once

#include "../ui_state.h"
#include "../workbench.h"

namespace app {

void drawMenuBar(Workbench& wb, UiState& ui);
void drawModelsPanel(Workbench& wb, UiState& ui);
void drawParametersPanel(Workbench& wb, UiState& ui);
void drawPencilPanel(Workbench& wb, UiState& ui);
void drawErrorsPanel(Workbench& wb, UiState& ui);
void drawTimingsPanel(Workbench& wb, UiState& ui);
void drawLitSpherePanel(Workbench& wb, UiState& ui);
void drawPointCloudPanel(Workbench& wb, UiState& ui);
void drawOctreePanel(Workbench& wb, UiState& ui);
void drawIrradiancePanel(Workbench& wb, UiState& ui);
void drawRenderPanel(Workbench& wb, UiState& ui);
void drawTraversalPanel(Workbench& wb, UiState& ui);

// Records the current state as captures/<name> (File → Record capture). Defined in capture_io.
std::string recordCapture(Workbench& wb, const std::string& name);

} // namespace app
