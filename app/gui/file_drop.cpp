// Files dropped on the window (file_drop.h).
#include "gui/file_drop.h"

#include "core/core.h"
#include "gui/panels/panels.h"

#include <algorithm>
#include <cctype>

namespace app {
namespace fs = std::filesystem;

namespace {

std::string lowerExtension(const fs::path& file) {
    std::string ext = file.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

// A scene file (mesh, environment) set as `setting`; the scene reads it again.
void setSceneFile(Workbench& wb, UiShared& ui, std::string& setting, const fs::path& file,
                  const char* what) {
    setting = fs::absolute(file).lexically_normal().string();
    wb.scene().reloadFiles();
    ui.status = std::string(what) + " " + file.filename().string();
    core::logInfo(std::string("dropped: ") + what + " " + setting);
}

} // namespace

void openDroppedFiles(Workbench& wb, UiState& ui, const std::vector<fs::path>& files) {
    for (const fs::path& file : files) {
        const std::string ext = lowerExtension(file);
        std::error_code ec;
        if (!fs::is_regular_file(file, ec)) {
            wb.reportActionError("dropped " + file.string() + ": not a file");
            continue;
        }
        SceneSettings& scene = wb.scene().settings();
        if (ext == ".bssrdf") {
            openModelFile(wb, ui.shared, file);
            ui.shared.show(PanelId::Models);
        } else if (ext == ".obj") {
            setSceneFile(wb, ui.shared, scene.meshFile, file, "mesh");
            ui.shared.show(PanelId::Render);
        } else if (ext == ".exr") {
            if (irradiance::hasVisibilityFactor(scene.light.mode)) // a directional light
                scene.light.mode = irradiance::LightMode::Ibl;
            setSceneFile(wb, ui.shared, scene.environmentFile, file, "environment");
            ui.shared.show(PanelId::Irradiance);
        } else if (ext == ".mco") {
            openMcmlFile(wb, ui.shared, file);
            ui.shared.show(PanelId::Pencil);
        } else {
            wb.reportActionError("dropped " + file.string() +
                                 ": not a file the workbench opens (a .bssrdf model, an .obj "
                                 "mesh, an .exr environment or an .mco MCML output)");
        }
    }
}

} // namespace app
