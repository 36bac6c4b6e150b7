// Errors panel: the current problems (file:line: message), one entry per problem; Log panel:
// the log, filtered by level.
#include "gui/panels/panels.h"
#include "gui/widgets.h"

#include "core/core.h"

#include <imgui.h>

#include <algorithm>

namespace app {

void drawErrorsPanel(Workbench& wb, ErrorsPanelState&, UiShared&) {
    auto errors = wb.errors();
    if (errors.empty()) ImGui::TextDisabled("No problems.");
    for (size_t i = 0; i < errors.size(); ++i) {
        const ErrorItem& e = errors[i];
        // the first line is the problem; what follows (a compiler's cascade) is folded
        const size_t newline = e.text.find('\n');
        ImGui::TextColored(ImVec4(1, 0.45f, 0.45f, 1), "[%s]", e.source.c_str());
        ImGui::SameLine();
        wrappedText("%s", e.text.substr(0, newline).c_str());
        if (newline == std::string::npos) continue;
        const std::string rest = e.text.substr(newline + 1);
        const long lines = 1 + std::count(rest.begin(), rest.end(), '\n');
        ImGui::PushID(int(i));
        if (ImGui::TreeNode("details", "%ld more line%s", lines, lines == 1 ? "" : "s")) {
            wrappedText("%s", rest.c_str());
            ImGui::TreePop();
        }
        ImGui::PopID();
    }
    if (!errors.empty() && ImGui::Button("Dismiss action errors")) wb.clearActionErrors();
}

void drawLogPanel(Workbench&, ErrorsPanelState& ps, UiShared&) {
    int& minLevel = ps.logMinLevel;
    setItemWidth(100, "level");
    ImGui::Combo("level", &minLevel, "debug\0info\0warning\0error\0");
    ImGui::SameLine();
    if (ImGui::Button("Clear")) core::logClear();
    ImGui::BeginChild("log", ImVec2(0, 0), false, ImGuiWindowFlags_HorizontalScrollbar);
    for (const auto& e : core::logSnapshot()) {
        if (static_cast<int>(e.level) < minLevel) continue;
        ImVec4 c = e.level == core::LogLevel::Error  ? ImVec4(1, 0.45f, 0.45f, 1)
                   : e.level == core::LogLevel::Warn ? ImVec4(1, 0.8f, 0.4f, 1)
                                                     : ImVec4(0.8f, 0.8f, 0.8f, 1);
        ImGui::TextColored(c, "%8.3f %s", e.seconds, e.text.c_str());
    }
    if (ImGui::GetScrollY() >= ImGui::GetScrollMaxY()) ImGui::SetScrollHereY(1.0f);
    ImGui::EndChild();
}

} // namespace app
