// Octree panel (thesis 3.3.1, 3.3.3, Figs. 3.4–3.5): node boxes of one level (slider) over the
// points, the depth histogram, leaf occupancy, memory and build time, and a decoder for a
// selected node — its 32-bit child descriptor bit by bit, children or points, attributes. With
// a traversal traced (debugger), the nodes it visited are drawn coloured by decision.
#include "gui/panels/panels.h"
#include "gui/widgets.h"

#include <algorithm>
#include <cinttypes>

namespace app {
namespace {

constexpr float kOctreeSplat = 2.0f; // the points' side in the view, UI units

glm::vec3 decisionColor(octree::Decision d) {
    switch (d) {
    case octree::Decision::Recurse:
        return {0.55f, 0.55f, 0.6f};
    case octree::Decision::EvaluateNode:
        return {1.0f, 0.55f, 0.1f};
    case octree::Decision::EvaluatePoints:
        return {0.2f, 0.9f, 0.3f};
    }
    return glm::vec3(1.0f);
}

void updateBoxes(Workbench& wb, OctreePanelState& ps, const UiShared& ui, const octree::Octree& t) {
    const bool trace = ui.inspect.highlightTrace && ui.inspect.debug && ui.inspect.debug->hit;
    std::string key =
        std::to_string(ps.level) + '|' + std::to_string(t.nodes.size()) + '|' +
        std::to_string(t.stats.nodesPerDepth.size()) + '|' + std::to_string(ps.selectedNode) + '|' +
        (trace ? std::to_string(ui.inspect.debug->x) + ',' + std::to_string(ui.inspect.debug->y) +
                     ',' + std::to_string(ui.inspect.debug->trace.steps.size())
               : "-");
    if (!ps.view) ps.view = std::make_unique<SceneView>();
    auto it = wb.scene().stats().find("scene.octree");
    key += '|' + std::to_string(it == wb.scene().stats().end() ? 0 : it->second.runs);
    if (key == ps.boxesKey) return;
    ps.boxesKey = key;
    std::vector<ViewBox> boxes;
    auto boxOf = [&](uint32_t n, glm::vec3 c) {
        const auto& r = t.nodes[n];
        return ViewBox{
            {r.boxMin[0], r.boxMin[1], r.boxMin[2]}, {r.boxMax[0], r.boxMax[1], r.boxMax[2]}, c};
    };
    if (trace) {
        for (const auto& s : ui.inspect.debug->trace.steps)
            boxes.push_back(boxOf(s.node, decisionColor(s.decision)));
    } else {
        for (uint32_t n = 0; n < t.descriptors.size() && boxes.size() < 60000; ++n)
            if (int(t.depth[n]) == ps.level)
                boxes.push_back(boxOf(
                    n, core::colorRamp(float(ps.level) / float(std::max(1, t.stats.maxDepth)))));
    }
    if (ps.selectedNode >= 0 && size_t(ps.selectedNode) < t.nodes.size())
        boxes.push_back(boxOf(uint32_t(ps.selectedNode), {1.0f, 1.0f, 1.0f}));
    ps.view->setBoxes(boxes);
    std::vector<glm::vec3> pos, col;
    for (const auto& p : t.points) {
        pos.push_back({p.positionArea[0], p.positionArea[1], p.positionArea[2]});
        col.push_back(glm::vec3(0.35f));
    }
    if (trace) { // the receiver
        pos.push_back(ui.inspect.debug->trace.xo);
        col.push_back({1.0f, 0.2f, 1.0f});
    }
    ps.view->setPoints(pos, col);
}

} // namespace

void drawOctreePanel(Workbench& wb, OctreePanelState& ps, UiShared& ui) {
    const octree::Octree* t = wb.scene().tree();
    if (!t) {
        hintText("no octree yet (it is built from the point cloud)");
        return;
    }
    const auto& s = t->stats;
    wrappedText("%zu nodes (%zu leaves), %zu points, depth %d, %.2f MiB, built in %.1f ms", s.nodes,
                s.leaves, s.points, s.maxDepth, double(s.bytes) / (1 << 20), s.buildMs);
    std::vector<float> depthHist(s.nodesPerDepth.begin(), s.nodesPerDepth.end());
    std::vector<float> occ(s.leafOccupancy.begin(), s.leafOccupancy.end());
    histogram("depth", depthHist, ImVec2(220, 50), "depth", 0, "nodes");
    sameLineIfFits(200);
    histogram("occupancy", occ, ImVec2(200, 50), "points in the leaf", 0, "leaves");
    setItemWidth(200, "level");
    ImGui::SliderInt("level", &ps.level, 0, s.maxDepth);
    sameLineIfFits(checkboxWidth("show traced pixel"));
    ImGui::Checkbox("show traced pixel", &ui.inspect.highlightTrace);
    if (ui.inspect.highlightTrace && ui.inspect.debug && ui.inspect.debug->hit)
        hintText("visited nodes: grey recurse, orange node evaluated, green leaf "
                 "points; magenta: the receiver");
    updateBoxes(wb, ps, ui, *t);
    const ImVec2 avail(visibleWidth(), ImGui::GetContentRegionAvail().y);
    const float side = std::max(120.0f, std::min(avail.x, avail.y - 170));
    float px = 0, py = 0;
    if (inspectorImage(wb, ui, *ps.view, ImVec2(side, side), kOctreeSplat, px, py)) {
        std::vector<glm::vec3> pos;
        for (const auto& p : t->points)
            pos.push_back({p.positionArea[0], p.positionArea[1], p.positionArea[2]});
        const render::Camera& cam = ui.inspect.camera;
        int slot = pickPoint(pos, cam.projection() * cam.view(), int(side), int(side), px, py,
                             kOctreeSplat);
        if (slot >= 0) // select the leaf holding the picked point
            for (uint32_t n = 0; n < t->descriptors.size(); ++n) {
                const uint32_t d = t->descriptors[n];
                if (octree::isLeaf(d) && uint32_t(slot) >= octree::descriptorIndex(d) &&
                    uint32_t(slot) < octree::descriptorIndex(d) + octree::pointCount(d))
                    ps.selectedNode = int(n);
            }
    }
    setItemWidth(120, "node");
    inputIntCommitted("node", &ps.selectedNode);
    ps.selectedNode = std::clamp(ps.selectedNode, 0, int(t->descriptors.size()) - 1);
    const uint32_t n = uint32_t(ps.selectedNode);
    const uint32_t d = t->descriptors[n];
    char bits[40];
    for (int b = 31, k = 0; b >= 0; --b) {
        bits[k++] = (d >> b) & 1u ? '1' : '0';
        if (b == 8 || b == 4) bits[k++] = ' ';
        bits[k] = 0;
    }
    ImGui::SameLine();
    wrappedText("0x%08" PRIx32 " = %s", d, bits);
    wrappedText("index(24) %u | points(4) %u | children(4) %u | depth %u, parent %u",
                octree::descriptorIndex(d), octree::pointCount(d), octree::childCount(d),
                t->depth[n], t->parent[n]);
    if (octree::isLeaf(d))
        ImGui::Text("leaf: points %u .. %u", octree::descriptorIndex(d),
                    octree::descriptorIndex(d) + octree::pointCount(d) - 1);
    else
        ImGui::Text("children: nodes %u .. %u", octree::descriptorIndex(d),
                    octree::descriptorIndex(d) + octree::childCount(d) - 1);
    const auto& r = t->nodes[n];
    wrappedText("sum E*A (%.4g, %.4g, %.4g), area %.4g", r.irradianceArea[0], r.irradianceArea[1],
                r.irradianceArea[2], r.irradianceArea[3]);
    wrappedText("mean P (%.4f, %.4f, %.4f)", r.meanPosition[0], r.meanPosition[1],
                r.meanPosition[2]);
    wrappedText("box (%.4f, %.4f, %.4f) .. (%.4f, %.4f, %.4f)", r.boxMin[0], r.boxMin[1],
                r.boxMin[2], r.boxMax[0], r.boxMax[1], r.boxMax[2]);
    wrappedText("covariance xx yy zz (%.3g, %.3g, %.3g), xy xz yz (%.3g, %.3g, %.3g)",
                r.covarianceDiagonal[0], r.covarianceDiagonal[1], r.covarianceDiagonal[2],
                r.covarianceOffDiagonal[0], r.covarianceOffDiagonal[1], r.covarianceOffDiagonal[2]);
}

} // namespace app
