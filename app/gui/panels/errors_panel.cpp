// Errors panel: the current problems (file:line: message), one entry per problem; Log panel:
// the log, filtered by level. Both copy what they show to the clipboard (a problem by itself
// from its right-click menu), to paste into an editor or a report.
#include "gui/panels/panels.h"
#include "gui/widgets.h"

#include "core/core.h"

#include <imgui.h>

#include <algorithm>
#include <cstdio>

namespace app {

namespace {
// A problem as the panel shows it, folded lines included.
std::string problemText(const ErrorItem& e) {
    return "[" + e.source + "] " + e.text + "\n";
}
} // namespace

void drawErrorsPanel(Workbench& wb, ErrorsPanelState& ps, UiShared& ui) {
    auto errors = wb.errors();
    if (errors.empty()) ImGui::TextDisabled("No problems.");
    for (size_t i = 0; i < errors.size(); ++i) {
        const ErrorItem& e = errors[i];
        ImGui::PushID(int(i));
        // the first line is the problem; what follows (a compiler's cascade) is folded
        const size_t newline = e.text.find('\n');
        ImGui::TextColored(ImVec4(1, 0.45f, 0.45f, 1), "[%s]", e.source.c_str());
        ImGui::SameLine();
        wrappedText("%s", e.text.substr(0, newline).c_str());
        if (ImGui::BeginPopupContextItem("problem")) {
            if (ImGui::MenuItem("Copy this problem")) {
                ImGui::SetClipboardText(problemText(e).c_str());
                ui.status = "copied a problem";
            }
            ImGui::EndPopup();
        }
        if (newline != std::string::npos) {
            const std::string rest = e.text.substr(newline + 1);
            const long lines = 1 + std::count(rest.begin(), rest.end(), '\n');
            if (ImGui::TreeNode("details", "%ld more line%s", lines, lines == 1 ? "" : "s")) {
                wrappedText("%s", rest.c_str());
                ImGui::TreePop();
            }
        }
        ImGui::PopID();
    }
    if (errors.empty()) return;
    if (ImGui::Button("Copy")) {
        std::string all;
        for (const ErrorItem& e : errors)
            all += problemText(e);
        ImGui::SetClipboardText(all.c_str());
        ui.status = "copied " + std::to_string(errors.size()) + " problem" +
                    (errors.size() == 1 ? "" : "s");
    }
    ps.copyErrors = lastItem();
    sameLineIfFits(buttonWidth("Dismiss action errors"));
    if (ImGui::Button("Dismiss action errors")) wb.clearActionErrors();
}

void drawLogPanel(Workbench&, ErrorsPanelState& ps, UiShared& ui) {
    int& minLevel = ps.logMinLevel;
    setItemWidth(100, "level");
    ImGui::Combo("level", &minLevel, "debug\0info\0warning\0error\0");
    ImGui::SameLine();
    if (ImGui::Button("Clear")) core::logClear();
    sameLineIfFits(buttonWidth("Copy"));
    const bool copy = ImGui::Button("Copy");
    ps.copyLog = lastItem();
    std::string copied;
    int copiedLines = 0;
    ImGui::BeginChild("log", ImVec2(0, 0), false, ImGuiWindowFlags_HorizontalScrollbar);
    for (const auto& e : core::logSnapshot()) {
        if (static_cast<int>(e.level) < minLevel) continue;
        ImVec4 c = e.level == core::LogLevel::Error  ? ImVec4(1, 0.45f, 0.45f, 1)
                   : e.level == core::LogLevel::Warn ? ImVec4(1, 0.8f, 0.4f, 1)
                                                     : ImVec4(0.8f, 0.8f, 0.8f, 1);
        ImGui::TextColored(c, "%8.3f %s", e.seconds, e.text.c_str());
        if (copy) {
            char time[32];
            std::snprintf(time, sizeof time, "%8.3f ", e.seconds);
            copied += time + e.text + "\n";
            ++copiedLines;
        }
    }
    if (copy) {
        ImGui::SetClipboardText(copied.c_str());
        ui.status =
            "copied " + std::to_string(copiedLines) + " log line" + (copiedLines == 1 ? "" : "s");
    }
    if (ImGui::GetScrollY() >= ImGui::GetScrollMaxY()) ImGui::SetScrollHereY(1.0f);
    ImGui::EndChild();
}

} // namespace app
