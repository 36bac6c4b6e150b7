// Lit spheres panel (thesis 3.6.2): the path-traced sphere and the selected model integrated
// over the sphere, same camera, light and radius in mm; tabs, side by side, signed difference
// or its z-score (in standard errors) with a colour bar; each image's relative standard error;
// HDR exposure and gamma; samples per pixel; progress; click a pixel for its value and standard
// error in both.
#include "gui/panels/panels.h"
#include "gui/widgets.h"

#include "core/text.h"
#include "pipeline/image_display.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>

namespace app {

namespace {

// Draws `rgba` (top row first) as an image of `side` pixels; a click selects a pixel.
void imageWithPick(gl::Texture& tex, const std::vector<uint8_t>& rgba, int w, int h, float side,
                   LitSpherePanelState& ps) {
    if (rgba.empty() || w <= 0) {
        ImGui::Dummy(ImVec2(side, side));
        return;
    }
    gl::uploadRGBA8(tex, w, h, rgba.data());
    ImVec2 pos = ImGui::GetCursorScreenPos();
    ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(tex.id())),
                 ImVec2(side, side));
    if (ImGui::IsItemClicked()) {
        ImVec2 m = ImGui::GetMousePos();
        ps.pickX = std::clamp(int((m.x - pos.x) / side * float(w)), 0, w - 1);
        ps.pickY = std::clamp(int((m.y - pos.y) / side * float(h)), 0, h - 1);
    }
    if (ps.pickX >= 0 && ps.pickY >= 0) { // mark the picked pixel
        const float s = side / float(w);
        ImVec2 a(pos.x + float(ps.pickX) * s, pos.y + float(ps.pickY) * s);
        ImGui::GetWindowDrawList()->AddRect(
            a, ImVec2(a.x + std::max(s, 3.0f), a.y + std::max(s, 3.0f)),
            IM_COL32(255, 255, 0, 255));
    }
}

void readout(const char* name, const pathtrace::Image& img, const LitSpherePanelState& ps) {
    auto v = pixelAt(img, ps.pickX, ps.pickY);
    if (!v.valid) return;
    wrappedText("%-18s R %.4g +- %.2g  G %.4g +- %.2g  B %.4g +- %.2g", name, v.mean[0],
                v.stderr_[0], v.mean[1], v.stderr_[1], v.mean[2], v.stderr_[2]);
}

void colourBar(float range) {
    ImDrawList* dl = ImGui::GetWindowDrawList();
    ImVec2 p = ImGui::GetCursorScreenPos();
    const float w = 240, h = 12;
    for (int i = 0; i < 48; ++i) {
        auto c = divergingColor(-1.0f + 2.0f * (float(i) + 0.5f) / 48.0f);
        dl->AddRectFilled(ImVec2(p.x + w * float(i) / 48, p.y),
                          ImVec2(p.x + w * float(i + 1) / 48, p.y + h),
                          IM_COL32(c[0], c[1], c[2], 255));
    }
    ImGui::Dummy(ImVec2(w, h));
    wrappedText("-%.3g (integrated brighter)   0   +%.3g (path traced brighter)", range, range);
}

} // namespace

void drawLitSpherePanel(Workbench& wb, LitSpherePanelState& ps, UiShared&) {
    LitSphereSettings& s = wb.litSphereSettings();
    ImGui::Checkbox("render", &s.enabled);
    float radius = float(s.radiusMm);
    sameLineItem(110, "radius [mm]");
    if (ImGui::DragFloat("radius [mm]", &radius, 0.1f, 0.1f, 1000.0f, "%.3g"))
        s.radiusMm = std::max(radius, 0.01f);
    sameLineItem(200, "light dir");
    if (ImGui::SliderFloat3("light dir", &s.lightDir.x, -1.0f, 1.0f, "%.2f")) {
        if (std::abs(s.lightDir[0]) + std::abs(s.lightDir[1]) + std::abs(s.lightDir[2]) < 1e-3f)
            s.lightDir[2] = 1.0f;
    }
    setItemWidth(90, "size");
    if (inputIntCommitted("size", &s.size, 32)) s.size = std::clamp(s.size, 16, 1024);
    sameLineItem(90, "path spp");
    if (inputIntCommitted("path spp", &s.pathSpp, 16)) s.pathSpp = std::clamp(s.pathSpp, 1, 100000);
    sameLineItem(110, "BSSRDF spp");
    if (inputIntCommitted("BSSRDF spp", &s.integratedSpp, 1024))
        s.integratedSpp = std::clamp(s.integratedSpp, 1, 10000000);
    sameLineIfFits(checkboxWidth("GPU path tracer"));
    ImGui::Checkbox("GPU path tracer", &s.gpu);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("GL compute tracer (shaders/pathtrace_sphere.comp, hot-reloaded), a "
                          "slice per frame;\noff: CPU tracer in a background thread");
    setItemWidth(260, "mesh (OBJ, empty: sphere)");
    pathFieldCommitted("mesh (OBJ, empty: sphere)", ps.meshBuffer, sizeof ps.meshBuffer, s.mesh);
    if (!s.mesh.empty())
        hintText("path tracing %s on the CPU and integrating the BSSRDF over it (longest axis "
                 "= 2 x radius)",
                 s.mesh.c_str());
    samplingChoice("BSSRDF sampling", s.sampling, s.axes);
    setItemWidth(120, "exposure");
    ImGui::SliderFloat("exposure", &ps.exposure, -10.0f, 10.0f, "%.1f EV");
    sameLineItem(120, "gamma");
    ImGui::SliderFloat("gamma", &ps.gamma, 0.5f, 4.0f, "%.2f");
    if (!s.enabled) {
        hintText("Renders the first visible (or soloed) model's material both ways.");
        return;
    }
    const auto& pt = wb.litSpheres().pathTracer();
    wrappedText("model %s | path traced %d / %d spp (%.3g paths/s) | integrated %llu / %d spp",
                wb.litSpheres().model().c_str(), pt.sppDone(), pt.sppTarget(), pt.pathsPerSecond(),
                (unsigned long long)wb.litSpheres().integratedSppDone(), s.integratedSpp);
    if (pt.sppDone() < pt.sppTarget()) {
        sameLineIfFits(buttonWidth("cancel path tracing"));
        if (ImGui::SmallButton("cancel path tracing")) wb.litSpheres().cancel();
    }
    if (const std::string problem = wb.litSpheres().problem(); !problem.empty())
        colouredText(ImVec4(1, 0.45f, 0.45f, 1), "%s", problem.c_str());

    const pathtrace::Image a = wb.litSpheres().pathTracer().image(),
                           b = wb.litSpheres().integratedImage();
    // how noisy each image is, so a difference can be read against it
    auto pct = [](double v) {
        return std::isfinite(v) ? core::formatNumber(100 * v, 2) + " %" : std::string("-");
    };
    ps.relSe[0] = relativeStandardError(a);
    ps.relSe[1] = relativeStandardError(b);
    wrappedText("relative standard error (median over lit pixels): path traced %s, integrated %s",
                pct(ps.relSe[0]).c_str(), pct(ps.relSe[1]).c_str());
    const float avail = visibleWidth();
    if (ImGui::BeginTabBar("views")) {
        const char* names[4] = {"Path traced", "BSSRDF integrated", "Side by side", "Difference"};
        // a view chosen from outside (state restore, a capture opened, tests) selects its tab:
        // SetSelected acts a frame late, and a tab bar drawn for the first time opens its first
        // tab meanwhile, which must not overwrite the view asked for
        const int shown = static_cast<int>(ps.view);
        const int wanted = shown != ps.viewShown ? shown : -1;
        int opened = -1;
        for (int i = 0; i < 4; ++i)
            if (ImGui::BeginTabItem(names[i], nullptr,
                                    i == wanted ? ImGuiTabItemFlags_SetSelected : 0)) {
                opened = i;
                ImGui::EndTabItem();
            }
        if (wanted < 0 && opened >= 0) ps.view = static_cast<SphereView>(opened);
        if (wanted < 0 || opened == wanted) ps.viewShown = static_cast<int>(ps.view);
        ImGui::EndTabBar();
    }
    const bool both = ps.view == SphereView::SideBySide;
    const float side = std::min(both ? avail * 0.5f - 8 : avail, 420.0f);
    if (ps.view == SphereView::PathTraced || both)
        imageWithPick(ps.tex[0], tonemap(a, ps.exposure, ps.gamma), a.width, a.height, side, ps);
    if (both) ImGui::SameLine();
    if (ps.view == SphereView::Integrated || both)
        imageWithPick(ps.tex[1], tonemap(b, ps.exposure, ps.gamma), b.width, b.height, side, ps);
    if (ps.view == SphereView::Difference) {
        int mode = ps.diffZ ? 1 : 0;
        ImGui::RadioButton("difference", &mode, 0);
        ImGui::SameLine();
        ImGui::RadioButton("z-score (in standard errors)", &mode, 1);
        {
            const ImVec2 lo = ImGui::GetItemRectMin(), hi = ImGui::GetItemRectMax();
            ps.zRadio = {lo.x, lo.y, hi.x, hi.y};
        }
        ps.diffZ = mode == 1;
        if (ps.diffZ) {
            imageWithPick(ps.tex[2], zMap(a, b, ps.zRange), a.width, a.height, side, ps);
            colourBar(ps.zRange);
            hintText("z = (path traced - integrated) / sqrt(var + var) of the luminance; grey: "
                     "|z| < 2 (within the noise); magenta: a difference without variance");
            setItemWidth(160, "z range");
            ImGui::DragFloat("z range", &ps.zRange, 0.05f, 1.0f, 100.0f, "%.3g");
        } else {
            float range = ps.diffRange > 0 ? ps.diffRange : maxAbsDifference(a, b);
            imageWithPick(ps.tex[2], differenceMap(a, b, range), a.width, a.height, side, ps);
            colourBar(range);
            setItemWidth(160, "range (0: auto)");
            ImGui::DragFloat("range (0: auto)", &ps.diffRange, 0.001f, 0.0f, 10.0f, "%.4g");
        }
    }
    if (ps.pickX >= 0) {
        wrappedText("pixel (%d, %d): radiant exitance per unit irradiance", ps.pickX, ps.pickY);
        readout("path traced", a, ps);
        readout("BSSRDF integrated", b, ps);
    } else {
        hintText("click a pixel for its value and standard error in both images");
    }
}

} // namespace app
