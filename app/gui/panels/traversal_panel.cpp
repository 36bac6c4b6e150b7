// Traversal debugger panel (thesis Algorithm 2): for the pixel clicked in the Render panel, the
// CPU replica's every step — node, depth, decision (recurse / evaluate node / evaluate leaf
// points), the solid angle, the whole packed stack after the step, the contribution and the
// running sum — in a scrollable, filterable table; the pixel's radiant exitance from the GPU
// readback, the CPU replica and brute force side by side; stack overflow and iteration-cap
// flags shown, never hidden; the steps shown copied to the clipboard as CSV (to diff two
// traversals). The pixel is traced again as the render changes (SceneInspect::follow) and the
// new trace compared with the one it replaced, or with a pinned baseline: steps, evaluations,
// stack depth, M, and the first step where they part, marked in the table. The Octree panel
// draws the visited nodes coloured by decision.
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

// The first step where `now` and `before` differ (node, depth or decision); the shorter trace's
// length when one is a prefix of the other; -1 when they are the same steps.
int firstDifferentStep(const octree::Trace& now, const octree::Trace& before) {
    const size_t n = std::min(now.steps.size(), before.steps.size());
    for (size_t i = 0; i < n; ++i) {
        const octree::Step &a = now.steps[i], &b = before.steps[i];
        if (a.node != b.node || a.depth != b.depth || a.decision != b.decision) return int(i);
    }
    return now.steps.size() == before.steps.size() ? -1 : int(n);
}

// What changed from `before` (the trace this one replaced, or the pinned baseline) to `now`.
void drawComparison(const PixelDebug& now, const PixelDebug& before, bool pinned, int firstDiff) {
    const octree::Trace &t = now.trace, &b = before.trace;
    const char* what = pinned ? "the pinned trace" : "the trace before";
    if (!before.hit) {
        wrappedText("%s: pixel (%d, %d) showed the background", what, before.x, before.y);
        return;
    }
    if (before.x != now.x || before.y != now.y)
        wrappedText("%s: pixel (%d, %d)", what, before.x, before.y);
    const float moved = glm::length(t.xo - b.xo);
    if (moved > 1e-6f)
        colouredText(ImVec4(1, 0.8f, 0.4f, 1),
                     "the pixel shows another surface point than %s (xo moved %.3g mesh units)",
                     what, double(moved));
    wrappedText("against %s: steps %zu -> %zu, evaluations %zu -> %zu, max stack depth %u -> "
                "%u; M change: CPU replica %.2e, GPU %.2e (relative)",
                what, b.steps.size(), t.steps.size(), b.evaluations.size(), t.evaluations.size(),
                b.maxStackDepth, t.maxStackDepth, relDiff(t.radiantExitance, b.radiantExitance),
                relDiff(now.gpuExitance, before.gpuExitance));
    if (firstDiff < 0) {
        hintText("the same steps (node, depth, decision) as %s", what);
    } else if (size_t(firstDiff) < std::min(t.steps.size(), b.steps.size())) {
        const octree::Step &x = t.steps[size_t(firstDiff)], &y = b.steps[size_t(firstDiff)];
        if (x.node == y.node)
            colouredText(ImVec4(1, 0.3f, 1, 1),
                         "first different step %d: node %u is '%s' now, '%s' before", firstDiff,
                         x.node, octree::decisionName(x.decision),
                         octree::decisionName(y.decision));
        else
            colouredText(ImVec4(1, 0.3f, 1, 1),
                         "first different step %d: node %u '%s' now, node %u '%s' before",
                         firstDiff, x.node, octree::decisionName(x.decision), y.node,
                         octree::decisionName(y.decision));
    } else {
        colouredText(ImVec4(1, 0.3f, 1, 1), "the same first %d steps, then %s", firstDiff,
                     t.steps.size() > b.steps.size() ? "more now" : "fewer now");
    }
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
    // what a change did to this pixel's traversal (SceneInspect::follow, previous, pinned)
    const PixelDebug* before = ui.inspect.pinned     ? &*ui.inspect.pinned
                               : ui.inspect.previous ? &*ui.inspect.previous
                                                     : nullptr;
    const int firstDiff = before && before->hit ? firstDifferentStep(t, before->trace) : -1;
    if (before) drawComparison(d, *before, ui.inspect.pinned.has_value(), firstDiff);
    ImGui::Checkbox("follow the render", &ui.inspect.follow);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("trace this pixel again on every new full-resolution frame (after a "
                          "change to eps, the model, a parameter, a shader or the camera) and "
                          "show what changed");
    ps.followBox = lastItem();
    sameLineIfFits(buttonWidth("Unpin the baseline"));
    if (ui.inspect.pinned ? ImGui::SmallButton("Unpin the baseline")
                          : ImGui::SmallButton("Pin as baseline")) {
        if (ui.inspect.pinned)
            ui.inspect.pinned.reset();
        else
            ui.inspect.pinned = d;
    }
    ps.pin = lastItem();
    if (ImGui::IsItemHovered() && !ui.inspect.pinned)
        ImGui::SetTooltip("compare the traces that follow with this one, not with the one each "
                          "replaced");
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
                if (rows[size_t(r)] == firstDiff) // where it parts from the compared trace
                    colouredText(ImVec4(1, 0.3f, 1, 1), "%d *", rows[size_t(r)]);
                else
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
