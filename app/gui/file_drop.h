// Files dropped on the window (GLFW's drop callback, gui.cpp): each opened as its extension says
// — a .bssrdf as a model (as File > Open model), an .obj as the scene's mesh, an .exr as the
// environment of image-based lighting (IBL chosen if the light was directional), an .mco as the
// pencil plot's MCML reference — with its panel brought to the front; anything else, or a file
// that is not there, is an Errors entry naming it.
#pragma once

#include "gui/ui_state.h"
#include "pipeline/workbench.h"

#include <filesystem>
#include <vector>

namespace app {

void openDroppedFiles(Workbench& wb, UiState& ui, const std::vector<std::filesystem::path>& files);

} // namespace app
