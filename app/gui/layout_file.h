// The layout file, imgui.ini in the user's configuration folder: ImGui's own window settings and
// a section of ours, [BssrdfWorkbench][Panels], one "key=value" line each — the open panels, the
// splitters, the floating panels' windows, each area's tab, the panels' view choices and numbers
// (exposure, gamma, the log's level), the recent
// models, the window's size in UI units. Unknown or malformed lines are ignored one by one: the
// defaults stand.
#pragma once

#include "gui/ui_state.h"

#include <filesystem>
#include <optional>
#include <utility>

namespace app {

// The user's configuration folder: $XDG_CONFIG_HOME/bssrdf-workbench, else
// ~/.config/bssrdf-workbench (the layout file, the sessions: captures/session.h).
std::filesystem::path configDir();
// configDir()/imgui.ini, the folder made if it was not there.
std::filesystem::path layoutFilePath();

// Adds our section's handler to the current ImGui context: its lines are read into `ui` and
// written from it (while that context lives).
void addLayoutHandler(UiState& ui);

// The window size the last session saved (Window=W,H), when it holds two sizes in [320, 16384].
std::optional<std::pair<int, int>> rememberedWindowSize();

} // namespace app
