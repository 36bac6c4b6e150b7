// The export controls of a panel (Render, Pencil plot): a name field, then one "Export <EXT>"
// button per extension (".exr" → "Export EXR"); a click opens a Save dialog (file_dialog.h, popup
// `popupId`) proposing the name in the folder of the last export.
#pragma once

#include "gui/file_dialog.h"

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace app {

// Returns the chosen absolute path, its extension added when missing, in the frame it is chosen;
// `name` follows the chosen file's stem. `buttons`, when given, receives each button's rectangle
// (x0, y0, x1, y1; tests click them).
std::optional<std::filesystem::path>
drawExportButtons(const char* popupId, char* name, size_t nameSize,
                  const std::vector<std::string>& extensions, ExportState& st,
                  std::vector<std::array<float, 4>>* buttons = nullptr);

} // namespace app
