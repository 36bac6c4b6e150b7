// Traversal debugger panel (thesis Algorithm 2): for the pixel clicked in the Render panel, the
// CPU replica's every step — node, depth, decision (recurse / evaluate node / evaluate leaf
// points), the solid angle, the whole packed stack after the step, the contribution and the
// running sum — in a scrollable, filterable table; the pixel's radiant exitance from the GPU
// readback, the CPU replica and brute force side by side; stack overflow and iteration-cap
// flags shown, never hidden; the steps shown copied to the clipboard as CSV (to diff two
// traversals). The Octree panel draws the visited nodes coloured by decision.
#include "gui/panels/panels.h"
#include "gui/widgets.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

namespace app {
namespace {

std::string stackText(const std::vector<uint32_t>& stack) {
    std::string s;
    char b[32];
    for (uint32_t e : stack) {
        std::snprintf(b, sizeof b, "%s%u:%u", s.empty() ? "" : " ", octree::stackNode(e),
                      octree::stackChildnum(e));
        s += b;
    }
    return s.empty() ? "(empty)" : s;
}

std::string flagText(uint32_t flags) {
    std::string s;
    if (flags & octree::kFlagStackOverflow) s += "STACK OVERFLOW ";
    if (flags & octree::kFlagIterationCap) s += "ITERATION CAP ";
    if (flags & render::kFlagLoopLimit) s += "DRIVER LOOP LIMIT ";
    return s.empty() ? "none" : s;
}

// The steps `rows` of `d`'s trace as CSV: a comment naming the pixel, a header, a line a step
// with the RGB contribution and running sum in full.
std::string stepsCsv(const PixelDebug& d, const std::vector<int>& rows) {
    std::string csv = "# traversal of pixel (" + std::to_string(d.x) + ", " + std::to_string(d.y) +
                      "), CPU replica\n" +
                      "step,node,depth,decision,solid_angle,stack_after,contribution_r,"
                      "contribution_g,contribution_b,running_sum_r,running_sum_g,running_sum_b\n";
    char line[512];
    for (int r : rows) {
        const octree::Step& s = d.trace.steps[size_t(r)];
        std::snprintf(line, sizeof line, "%d,%u,%u,%s,%.9g,%s,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", r,
                      s.node, s.depth, octree::decisionName(s.decision), double(s.solidAngle),
                      stackText(s.stack).c_str(), double(s.contribution.x),
                      double(s.contribution.y), double(s.contribution.z), double(s.runningSum.x),
                      double(s.runningSum.y), double(s.runningSum.z));
        csv += line;
    }
    return csv;
}

float relDiff(const glm::vec3& a, const glm::vec3& b) {
    const float den = std::max({std::abs(b.x), std::abs(b.y), std::abs(b.z), 1e-30f});
    return std::max({std::abs(a.x - b.x), std::abs(a.y - b.y), std::abs(a.z - b.z)}) / den;
}

} // namespace

void drawTraversalPanel(Workbench& wb, TraversalPanelState& ps, UiShared& ui) {
    (void)wb;
    if (!ui.inspect.debug) {
        hintText("click a pixel in the Render panel to trace its octree traversal");
        return;
    }
    const PixelDebug& d = *ui.inspect.debug;
    if (!d.hit) {
        wrappedText("pixel (%d, %d) shows the background (no surface)", d.x, d.y);
        return;
    }
    const octree::Trace& t = d.trace;
    wrappedText("pixel (%d, %d)  xo (%.4f, %.4f, %.4f)  no (%.3f, %.3f, %.3f)", d.x, d.y, t.xo.x,
                t.xo.y, t.xo.z, t.no.x, t.no.y, t.no.z);
    // M from the GPU readback, its CPU replica and brute force, a column per channel with as
    // many significant digits (3 to 7) as the column shows
    if (ImGui::BeginTable("exitance", 4, ImGuiTableFlags_SizingStretchSame,
                          ImVec2(visibleWidth(), 0))) {
        ImGui::TableSetupColumn("M", ImGuiTableColumnFlags_WidthFixed);
        for (const char* c : {"R", "G", "B"})
            ImGui::TableSetupColumn(c);
        ImGui::TableHeadersRow();
        const std::pair<const char*, glm::vec3> rows[] = {
            {"GPU", d.gpuExitance}, {"CPU", t.radiantExitance}, {"brute", d.bruteExitance}};
        const float digit = ImGui::CalcTextSize("0").x;
        for (const auto& [name, m] : rows) {
            ImGui::TableNextRow();
            ImGui::TableNextColumn();
            ImGui::TextUnformatted(name);
            for (int c = 0; c < 3; ++c) {
                ImGui::TableNextColumn();
                const int digits =
                    std::clamp(int(ImGui::GetContentRegionAvail().x / digit) - 1, 3, 7);
                ImGui::Text("%.*g", digits, double(m[c]));
            }
        }
        ImGui::EndTable();
    }
    wrappedText("CPU replica vs GPU: relative difference %.2e; hierarchy error (CPU replica vs "
                "brute force) %.2e",
                relDiff(t.radiantExitance, d.gpuExitance),
                relDiff(t.radiantExitance, d.bruteExitance));
    wrappedText("steps: GPU %u, CPU %zu | max stack depth: GPU %u, CPU %u | evaluations: GPU %u, "
                "CPU %zu",
                d.gpuStats.x, t.steps.size(), d.gpuStats.y, t.maxStackDepth, d.gpuStats.w,
                t.evaluations.size());
    const bool flagged = t.flags != 0 || d.gpuStats.z != 0;
    colouredText(flagged ? ImVec4(1, 0.3f, 1, 1) : ImVec4(0.6f, 0.9f, 0.6f, 1),
                 "flags: GPU %s | CPU %s", flagText(d.gpuStats.z).c_str(),
                 flagText(t.flags).c_str());
    if (t.closestMargin < 1e-5f)
        colouredText(ImVec4(1, 0.8f, 0.3f, 1),
                     "a criterion test was within %.1e of its threshold: CPU and GPU "
                     "rounding may decide it differently",
                     t.closestMargin);
    const bool show3d = ImGui::SmallButton("nodes in 3D");
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("show the visited nodes in the Octree panel");
    if (show3d) {
        ui.show(PanelId::Octree);
        ui.inspect.highlightTrace = true;
    }
    ImGui::Checkbox("recurse", &ps.showRecurse);
    sameLineIfFits(checkboxWidth("node"));
    ImGui::Checkbox("node", &ps.showNodeEval);
    sameLineIfFits(checkboxWidth("points"));
    ImGui::Checkbox("points", &ps.showPointEval);
    sameLineItem(140, "node # filter");
    ImGui::InputText("node # filter", ps.filter, sizeof ps.filter);
    std::vector<int> rows;
    for (size_t i = 0; i < t.steps.size(); ++i) {
        const octree::Step& s = t.steps[i];
        if (s.decision == octree::Decision::Recurse && !ps.showRecurse) continue;
        if (s.decision == octree::Decision::EvaluateNode && !ps.showNodeEval) continue;
        if (s.decision == octree::Decision::EvaluatePoints && !ps.showPointEval) continue;
        if (ps.filter[0] && std::to_string(s.node).find(ps.filter) == std::string::npos) continue;
        rows.push_back(int(i));
    }
    ImGui::Text("%zu of %zu steps", rows.size(), t.steps.size());
    sameLineIfFits(buttonWidth("Copy steps (CSV)"));
    if (ImGui::Button("Copy steps (CSV)")) {
        ImGui::SetClipboardText(stepsCsv(d, rows).c_str());
        ui.status = "copied " + std::to_string(rows.size()) + " traversal steps";
    }
    ps.copySteps = lastItem();
    if (ImGui::BeginTable("trace", 8,
                          ImGuiTableFlags_ScrollX | ImGuiTableFlags_ScrollY |
                              ImGuiTableFlags_RowBg | ImGuiTableFlags_Resizable |
                              ImGuiTableFlags_BordersInnerV)) {
        ImGui::TableSetupScrollFreeze(0, 1);
        for (const char* h : {"step", "node", "depth", "decision", "solid angle", "stack after",
                              "contribution (lum)", "running sum (lum)"})
            ImGui::TableSetupColumn(h);
        ImGui::TableHeadersRow();
        ImGuiListClipper clip;
        clip.Begin(int(rows.size()));
        while (clip.Step())
            for (int r = clip.DisplayStart; r < clip.DisplayEnd; ++r) {
                const octree::Step& s = t.steps[size_t(rows[size_t(r)])];
                ImGui::TableNextRow();
                ImGui::TableNextColumn();
                ImGui::Text("%d", rows[size_t(r)]);
                ImGui::TableNextColumn();
                ImGui::Text("%u", s.node);
                ImGui::TableNextColumn();
                ImGui::Text("%u", s.depth);
                ImGui::TableNextColumn();
                ImGui::TextUnformatted(octree::decisionName(s.decision));
                ImGui::TableNextColumn();
                ImGui::Text("%.4g", s.solidAngle);
                ImGui::TableNextColumn();
                ImGui::TextUnformatted(stackText(s.stack).c_str());
                ImGui::TableNextColumn();
                const glm::vec3 c = s.contribution, sum = s.runningSum;
                ImGui::Text("%.4g", luminance(c));
                ImGui::TableNextColumn();
                ImGui::Text("%.6g", luminance(sum));
            }
        ImGui::EndTable();
    }
}

} // namespace app
