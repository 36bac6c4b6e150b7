// Timings panel: per stage CPU and GPU (GL timer query) time, run count, and the measured
// hot-reload latency from file save to new pixels.
#include "gui/panels/panels.h"

#include "gl/gl.h"

#include <imgui.h>

namespace app {

void drawTimingsPanel(Workbench&, UiShared&) {
    ImGui::Text("frame %.2f ms (%.0f fps)", 1000.0f / ImGui::GetIO().Framerate,
                ImGui::GetIO().Framerate);
    if (ImGui::BeginTable("timings", 4,
                          ImGuiTableFlags_RowBg | ImGuiTableFlags_Borders |
                              ImGuiTableFlags_SizingFixedFit)) {
        ImGui::TableSetupColumn("stage", ImGuiTableColumnFlags_WidthStretch);
        ImGui::TableSetupColumn("CPU ms", ImGuiTableColumnFlags_WidthFixed, 60);
        ImGui::TableSetupColumn("GPU ms", ImGuiTableColumnFlags_WidthFixed, 60);
        ImGui::TableSetupColumn("runs", ImGuiTableColumnFlags_WidthFixed, 36);
        ImGui::TableHeadersRow();
        for (const auto& t : gl::timings()) {
            ImGui::TableNextRow();
            ImGui::TableNextColumn();
            ImGui::TextWrapped("%s", t.stage.c_str()); // a stage named after a long file
            ImGui::TableNextColumn();
            ImGui::Text("%.3f", t.cpuMs);
            ImGui::TableNextColumn();
            if (t.gpuMs >= 0) {
                ImGui::Text("%.3f", t.gpuMs);
            } else {
                ImGui::TextDisabled("n/a");
                if (ImGui::IsItemHovered())
                    ImGui::SetTooltip(t.gpuUnmeasurable
                                          ? "the driver's GPU timer reported 0 ns: it cannot "
                                            "time this work (e.g. llvmpipe)"
                                          : "no GPU time: the stage runs inside another timed "
                                            "stage, on the CPU only, or its result is pending");
            }
            ImGui::TableNextColumn();
            ImGui::Text("%lld", t.runs);
        }
        ImGui::EndTable();
    }
    ImGui::TextDisabled("hot reload target: <= 150 ms save -> pixels");
}

} // namespace app
