// Point cloud panel (thesis 2.6.4, 3.3.1, the "most useful widget" of 3.6.4): the mesh and
// point-cloud settings (file, count, method, seed, cache, a PLY loaded directly), the points as
// splats coloured by normal, area, irradiance or radiance with a colour bar, the count, the
// uniformity metrics and the generation time; click a point for all its values.
#include "gui/panels/panels.h"
#include "gui/widgets.h"

#include "render/frame_analysis.h"

#include <algorithm>
#include <cmath>

namespace app {
namespace {

constexpr float kCloudSplat = 3.0f; // the points' side in the view, UI units

long long runsOf(const SceneStage& s, const char* stage) {
    auto it = s.stats().find(stage);
    return it == s.stats().end() ? 0 : it->second.runs;
}

// Radiance of each point as the last frame shows it: the HDR pixel the point projects to, when
// the G-buffer there is the point's own surface (within `tol`); −1 when hidden or outside.
void uploadColors(Workbench& wb, PointCloudPanelState& ps, const UiShared& ui) {
    SceneStage& scene = wb.scene();
    const auto& pts = scene.cloud().points;
    std::string key = std::to_string(int(ui.inspect.colorBy)) + '|' +
                      std::to_string(runsOf(scene, "scene.pointcloud")) + '|' +
                      std::to_string(runsOf(scene, "scene.irradiance")) +
                      (ui.inspect.colorBy == PointColor::Radiance
                           ? '|' + std::to_string(runsOf(scene, "scene.render"))
                           : "");
    if (key == ps.colorsKey && ps.view) return;
    ps.colorsKey = key;
    if (!ps.view) ps.view = std::make_unique<SceneView>();
    std::vector<glm::vec3> pos(pts.size()), col(pts.size());
    std::vector<float> value(pts.size(), 0.0f);
    for (size_t i = 0; i < pts.size(); ++i)
        pos[i] = {pts[i].p[0], pts[i].p[1], pts[i].p[2]};
    const auto& e = scene.irradiance();
    if (ui.inspect.colorBy == PointColor::Area)
        for (size_t i = 0; i < pts.size(); ++i)
            value[i] = pts[i].area;
    if (ui.inspect.colorBy == PointColor::Irradiance)
        for (size_t i = 0; i < pts.size() && i < e.size(); ++i)
            value[i] = luminance(e[i]);
    if (ui.inspect.colorBy == PointColor::Radiance)
        value = scene.hasFrame()
                    ? render::radianceAtPoints(scene.readback(), scene.settings().render.camera,
                                               pos, 2.0f * float(scene.uniformity().meanNN) + 1e-4f)
                    : std::vector<float>(pos.size(), -1.0f);
    float lo = 1e30f, hi = -1e30f;
    for (float v : value)
        if (v >= 0) lo = std::min(lo, v), hi = std::max(hi, v);
    if (lo > hi) lo = hi = 0;
    ps.colorMin = lo;
    ps.colorMax = hi;
    for (size_t i = 0; i < pts.size(); ++i) {
        if (ui.inspect.colorBy == PointColor::Normal)
            col[i] = glm::vec3(pts[i].n[0], pts[i].n[1], pts[i].n[2]) * 0.5f + 0.5f;
        else if (value[i] < 0)
            col[i] = glm::vec3(0.3f);
        else
            col[i] = core::colorRamp(hi > lo ? (value[i] - lo) / (hi - lo) : 0.5f);
    }
    ps.view->setPoints(pos, col);
}

// A ring on the picked point where the camera projects it now (it follows an orbit): yellow
// when the point faces the camera, grey when it faces away (seen through the mesh).
void markPickedPoint(PointCloudPanelState& ps, const pointcloud::PointCloud& cloud,
                     const render::Camera& cam) {
    ps.pickedMarker = glm::vec2(-1.0f);
    if (ps.picked < 0 || size_t(ps.picked) >= cloud.points.size()) return;
    const auto& pt = cloud.points[size_t(ps.picked)];
    const glm::vec3 p(pt.p[0], pt.p[1], pt.p[2]), n(pt.n[0], pt.n[1], pt.n[2]);
    const glm::vec4 c = cam.projection() * cam.view() * glm::vec4(p, 1.0f);
    if (!(c.w > 0)) return;
    const Rect& r = ps.imageRect;
    const glm::vec2 at(r.x0 + (c.x / c.w * 0.5f + 0.5f) * r.width(),
                       r.y0 + (0.5f - c.y / c.w * 0.5f) * r.height());
    if (at.x < r.x0 || at.x > r.x1 || at.y < r.y0 || at.y > r.y1) return;
    ps.pickedMarker = at;
    ps.pickedFacing = glm::dot(n, cam.position() - p) > 0;
    ImGui::GetWindowDrawList()->AddCircle(
        ImVec2(at.x, at.y), 6.0f,
        ps.pickedFacing ? IM_COL32(255, 225, 0, 255) : IM_COL32(170, 170, 170, 255), 16, 2.0f);
}

} // namespace

void drawPointCloudPanel(Workbench& wb, PointCloudPanelState& ps, UiShared& ui) {
    SceneStage& scene = wb.scene();
    SceneSettings& s = scene.settings();
    setItemWidth(300, "mesh (OBJ)");
    if (pathFieldCommitted("mesh (OBJ)", ps.meshBuffer, sizeof ps.meshBuffer, s.meshFile))
        scene.reloadFiles(); // Enter on the same name reads the file again
    int n = int(s.points.points);
    setItemWidth(120, "points");
    if (inputIntCommitted("points", &n, 1000, 10000)) s.points.points = size_t(std::max(n, 0));
    ImGui::SameLine();
    constexpr auto methods = enumNames(pointcloud::Method{});
    const char* names[methods.size()];
    int m = 0;
    for (size_t k = 0; k < methods.size(); ++k) {
        names[k] = methods[k].second;
        if (s.points.method == methods[k].first) m = int(k);
    }
    setItemWidth(170, "method");
    if (ImGui::Combo("method", &m, names, int(methods.size())))
        s.points.method = methods[size_t(m)].first;
    int seed = int(s.points.seed);
    setItemWidth(90, "seed");
    if (inputIntCommitted("seed", &seed)) s.points.seed = uint64_t(std::max(seed, 0));
    using pointcloud::Method;
    if (s.points.method == Method::Repulsion || s.points.method == Method::StratifiedRepulsion) {
        sameLineItem(90, "iterations");
        int& it = s.points.method == Method::Repulsion ? s.points.repulsionIterations
                                                       : s.points.stratifiedIterations;
        if (inputIntCommitted("iterations", &it, 10, 100)) it = std::clamp(it, 0, 100000);
    }
    sameLineIfFits(checkboxWidth("disk cache"));
    ImGui::Checkbox("disk cache", &s.useCache);
    setItemWidth(300, "load PLY (empty: generate)");
    pathFieldCommitted("load PLY (empty: generate)", ps.plyBuffer, sizeof ps.plyBuffer,
                       s.pointCloudFile);

    if (scene.generating()) {
        colouredText(ImVec4(1, 0.8f, 0.3f, 1), "generating %zu points ... %.1f s", s.points.points,
                     scene.generatingSeconds());
        ImGui::SameLine();
        ImGui::ProgressBar(float(scene.generatingProgress()), ImVec2(160, 0), "relaxation");
        sameLineIfFits(buttonWidth("cancel"));
        if (ImGui::SmallButton("cancel")) scene.cancelPointCloud();
    }
    const auto& cloud = scene.cloud();
    if (cloud.points.empty()) {
        ImGui::TextDisabled("no point cloud yet");
        return;
    }
    const auto& u = scene.uniformity();
    auto st = scene.stats().find("scene.pointcloud");
    wrappedText("%zu points, area %.4g units^2 (A/N = %.3g), %s %.0f ms", cloud.points.size(),
                cloud.totalArea, cloud.totalArea / double(cloud.points.size()),
                scene.cloudFromCache() ? "read from cache in" : "made in",
                st != scene.stats().end() ? st->second.ms : 0.0);
    wrappedText("nearest neighbour: mean %.4g, CV %.4f, min/mean %.3f", u.meanNN, u.cvNN,
                u.meanNN > 0 ? u.minNN / u.meanNN : 0.0);
    const char* modes[] = {"normal", "area", "irradiance", "radiance (from the render)"};
    setItemWidth(200, "colour by");
    comboEnum("colour by", ui.inspect.colorBy, modes);
    uploadColors(wb, ps, ui);
    if (ui.inspect.colorBy != PointColor::Normal)
        rampBar(ps.colorMin, ps.colorMax,
                ui.inspect.colorBy == PointColor::Area         ? "units^2"
                : ui.inspect.colorBy == PointColor::Irradiance ? "(E_t luminance)"
                                                               : "(L_o luminance; grey: hidden)");
    const ImVec2 avail(visibleWidth(), ImGui::GetContentRegionAvail().y);
    const float side = std::max(120.0f, std::min(avail.x, avail.y - 40));
    float px = 0, py = 0;
    std::vector<glm::vec3> pos;
    const bool clicked = inspectorImage(wb, ui, *ps.view, ImVec2(side, side), kCloudSplat, px, py);
    ps.imageRect = lastItem();
    if (clicked) {
        pos.resize(cloud.points.size());
        for (size_t i = 0; i < pos.size(); ++i)
            pos[i] = {cloud.points[i].p[0], cloud.points[i].p[1], cloud.points[i].p[2]};
        render::Camera cam = ui.inspect.camera;
        ps.picked = pickPoint(pos, cam.projection() * cam.view(), int(side), int(side), px, py,
                              kCloudSplat);
        ps.pickedExitance = glm::vec3(-1.0f);
        if (ps.picked >= 0) {
            const auto& p = cloud.points[size_t(ps.picked)];
            try {
                ps.pickedExitance =
                    scene.exitanceAt({p.p[0], p.p[1], p.p[2]}, {p.n[0], p.n[1], p.n[2]});
            } catch (const std::exception&) { // no frame yet: the readout says so
            }
        }
    }
    markPickedPoint(ps, cloud, ui.inspect.camera);
    if (ps.picked >= 0 && size_t(ps.picked) < cloud.points.size()) {
        const auto& p = cloud.points[size_t(ps.picked)];
        wrappedText("point %d: p (%.4f, %.4f, %.4f)  n (%.3f, %.3f, %.3f)  area %.4g", ps.picked,
                    p.p[0], p.p[1], p.p[2], p.n[0], p.n[1], p.n[2], p.area);
        const auto& e = scene.irradiance();
        if (size_t(ps.picked) < e.size()) {
            const glm::vec3 v = e[size_t(ps.picked)];
            wrappedText("  E_t (%.4g, %.4g, %.4g)  triangle %u", v.x, v.y, v.z, p.triangle);
        }
        const glm::vec3 M = ps.pickedExitance;
        if (M.x >= 0)
            wrappedText("  radiant exitance M (%.4g, %.4g, %.4g); radiance L_o = Ft/pi * M", M.x,
                        M.y, M.z);
        else
            hintText("  radiant exitance: available once the scene has rendered");
    } else {
        hintText("drag to orbit, wheel to zoom, click a point for its values");
    }
}

} // namespace app
