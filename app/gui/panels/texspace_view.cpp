// The Render panel's texture-space renderer (seed 004): its settings, its status and the views
// of its stages — E′ in the texture, the mip CDF's levels, the drawn texels on the texture and
// on the mesh, the atlas with its distortion. Shows and edits only; texspace_stage.h does the
// work, texspace_images.h makes the stage images.
#include "gui/panels/panels.h"
#include "gui/widgets.h"
#include "pipeline/image_display.h"
#include "pipeline/texspace_images.h"

#include <glm/glm.hpp>
#include <imgui.h>

#include <algorithm>
#include <cmath>

namespace app {

namespace {

void showSquare(RenderPanelState& ps, const Rgba8Image& im, const texspace::SampleSet* dots) {
    if (im.width == 0) return;
    gl::uploadRGBA8(ps.tsTex, im.width, im.height, im.rgba.data());
    const ImVec2 avail(visibleWidth(), ImGui::GetContentRegionAvail().y);
    const float side = std::max(128.0f, std::min(avail.x, avail.y - 24.0f));
    const ImVec2 o = ImGui::GetCursorScreenPos();
    ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(ps.tsTex.id())),
                 ImVec2(side, side));
    if (ImGui::IsItemHovered()) {
        const ImVec2 m = ImGui::GetMousePos();
        const int i = std::clamp(int((m.x - o.x) / side * float(im.width)), 0, im.width - 1);
        const int j = std::clamp(int((m.y - o.y) / side * float(im.height)), 0, im.height - 1);
        ImGui::SetTooltip("texel (%d, %d) of %d²", i, im.height - 1 - j, im.width);
    }
    if (!dots) return;
    // the drawn texels, also as circles: a single texel is smaller than a screen pixel at K > side
    ImDrawList* dl = ImGui::GetWindowDrawList();
    const float k = float(im.width);
    for (uint32_t t : dots->texel) {
        const float u = (float(t % uint32_t(im.width)) + 0.5f) / k;
        const float v = (float(t / uint32_t(im.width)) + 0.5f) / k;
        dl->AddCircle(ImVec2(o.x + u * side, o.y + (1.0f - v) * side), 2.5f,
                      IM_COL32(60, 255, 90, 200));
    }
}

// The hybrid's weighting and local filter (texspace/hybrid.h).
void hybridControls(texspace::HybridSettings& h) {
    setItemWidth(90, "K");
    if (ImGui::InputFloat("K", &h.k, 0, 0, "%.3g", ImGuiInputTextFlags_EnterReturnsTrue))
        h.k = std::clamp(h.k, 1e-3f, 1e3f);
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("K of the weighting function W_l, 1/mm");
    sameLineItem(90, "bound");
    if (ImGui::InputFloat("bound", &h.lowerBound, 0, 0, "%.3g",
                          ImGuiInputTextFlags_EnterReturnsTrue))
        h.lowerBound = std::clamp(h.lowerBound, 1e-9f, 1e3f);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("importance lower bound: R_p is the largest r with R(r)·2πr at or "
                          "above it, 1/mm (thesis: 0.1)");
    sameLineItem(100, "rings");
    if (inputIntCommitted("rings", &h.rings, 1)) h.rings = std::clamp(h.rings, 1, 64);
    sameLineItem(100, "taps/ring");
    if (inputIntCommitted("taps/ring", &h.perRing, 1)) h.perRing = std::clamp(h.perRing, 1, 64);
}

} // namespace

bool drawTextureSpaceView(Workbench& wb, RenderPanelState& ps, const render::Frame& f,
                          GLuint& tex) {
    TextureSpaceSettings& ts = wb.textureSpaceSettings();
    texspace::Settings& s = ts.sampling;
    static const char* const kSizes[] = {"16", "32", "64", "128", "256", "512", "1024", "2048"};
    int sizeIndex = std::clamp(int(std::lround(std::log2(double(s.textureSize)))) - 4, 0, 7);
    setItemWidth(90, "texture");
    if (ImGui::Combo("texture", &sizeIndex, kSizes, 8)) s.textureSize = 16 << sizeIndex;
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("texels per side K of the texture-space E′");
    sameLineItem(110, "N");
    if (inputIntCommitted("N", &s.samples, 49)) s.samples = std::clamp(s.samples, 1, 1 << 20);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("texels drawn per sample set (seed 004 Table 4.2: 49 … 2500)");
    sameLineItem(110, "sets");
    if (inputIntCommitted("sets", &s.sampleSets, 16))
        s.sampleSets = std::clamp(s.sampleSets, 1, 1000000);
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("independent sample sets averaged");
    static const char* const kViews[] = {"render",        "E' (texture)",       "CDF level",
                                         "samples",       "atlas / distortion", "hybrid: local",
                                         "hybrid: global"};
    sameLineItem(150, "view");
    comboEnum("view", ps.tsView, kViews);
    if (s.hybrid) {
        hybridControls(s.local);
    } else if (ps.tsView == TextureSpaceView::Local || ps.tsView == TextureSpaceView::Global) {
        ps.tsView = TextureSpaceView::Render;
    }
    sameLineIfFits(checkboxWidth("samples on mesh"));
    ImGui::Checkbox("samples on mesh", &ps.tsSamplesOnMesh);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("the last set's texels as dots over the render (front-facing and "
                          "visible in the G-buffer)");

    TextureSpaceStage& stage = wb.textureSpace();
    for (const std::string& p : stage.problems())
        colouredText(ImVec4(1, 0.45f, 0.45f, 1), "%s", p.c_str());
    const texspace::Pipeline* p = stage.pipeline();
    if (!p || !p->hasMesh()) {
        hintText("waiting for the mesh and a usable model ...");
        return false;
    }
    const litsphere::Image img = stage.radiance();
    double var = 0, sum2 = 0;
    for (size_t i = 0; i < img.mean.size(); ++i)
        if (std::isfinite(img.variance[i])) {
            var += img.variance[i];
            sum2 += double(img.mean[i]) * img.mean[i];
        }
    wrappedText("%d / %d sets of N = %d, K = %d, %.1f s, relative standard error %.3g",
                p->setsDone(), p->setsTarget(), s.samples, p->texels().size, stage.seconds(),
                sum2 > 0 ? std::sqrt(var / sum2) : 0.0);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("covered texels %zu of %d²; they stand for %.4g of the mesh's area "
                          "(mesh units²)\nW = Σ Y(E′)·A_texel = %.4g\nlast set: %zu distinct "
                          "texels, drawn in %.1f ms, rendered in %.1f ms\n%s",
                          p->texels().covered, p->texels().size, p->representedArea(),
                          p->totalWeight(), p->lastSet().texel.size(), p->lastSampleMs(),
                          p->lastRenderMs(),
                          p->parameterization().fromMesh ? "the mesh's own UVs" : "atlas");
    if (!stage.note().empty()) hintText("atlas: %s", stage.note().c_str());
    if (s.hybrid && !p->hybridTaps().empty())
        hintText("hybrid: R_p %.3g, %.3g, %.3g mm (R·2πr meets %.3g/mm), K %.3g/mm, %zu taps, "
                 "local term %.1f ms",
                 p->hybridRp().x, p->hybridRp().y, p->hybridRp().z, double(s.local.lowerBound),
                 double(s.local.k), p->hybridTaps().size(), p->localMs());
    if (p->layoutSize() > p->texels().size)
        hintText("atlas laid out for %d² (gutters between %zu triangles), sampled at %d²",
                 p->layoutSize(), p->parameterization().uv.size(), p->texels().size);
    switch (ps.tsView) {
    case TextureSpaceView::Render:
    case TextureSpaceView::Local:
    case TextureSpaceView::Global: {
        const litsphere::Image part = ps.tsView == TextureSpaceView::Local    ? p->localRadiance()
                                      : ps.tsView == TextureSpaceView::Global ? p->globalRadiance()
                                                                              : img;
        if (part.width == f.width && part.height == f.height && part.width > 0) {
            const char* what = !s.hybrid                               ? "texture-space render"
                               : ps.tsView == TextureSpaceView::Local  ? "hybrid's local term"
                               : ps.tsView == TextureSpaceView::Global ? "hybrid's global term"
                                                                       : "hybrid render";
            tex = showEstimate(wb.scene(), ps, what, part, ps.tsTex);
            if (!stage.problems().empty())
                hintText("shown: the last texture-space image, made before the problem above");
        } else if (!stage.problems().empty()) {
            // the stage stopped on a problem: nothing is in progress, the frame is the
            // hierarchical render's
            hintText("no texture-space image of this view (the problem above); shown: the "
                     "hierarchical render");
        } else {
            hintText("texture-space image of the full-resolution view in progress ...");
        }
        return false;
    }
    case TextureSpaceView::Irradiance:
        showSquare(ps, eprimeImage(*p), nullptr);
        return true;
    case TextureSpaceView::CdfLevel: {
        const int levels = int(p->cdf().levels.size());
        if (levels == 0) {
            hintText("no CDF (no light reaches the surface)");
            return true;
        }
        setItemWidth(200, "level");
        ImGui::SliderInt("level", &ps.tsLevel, 0, levels - 1);
        ps.tsLevel = std::clamp(ps.tsLevel, 0, levels - 1);
        hintText("level %d: %d² sums of texel weights (log10, four decades); Algorithm 3.1 "
                 "descends from level %d",
                 ps.tsLevel, p->cdf().size >> ps.tsLevel, levels - 1);
        showSquare(ps, cdfLevelImage(p->cdf(), ps.tsLevel), nullptr);
        return true;
    }
    case TextureSpaceView::Samples:
        showSquare(ps, samplesImage(*p, p->lastSet()), &p->lastSet());
        return true;
    case TextureSpaceView::Atlas: {
        double worst = 1;
        for (double x : p->parameterization().stretch)
            worst = std::max(worst, x);
        hintText("colour: stretch s1/s2 (texture to surface) per triangle (dark 1, bright 4 or "
                 "more); largest %.3g",
                 worst);
        showSquare(ps, atlasImage(*p), nullptr);
        return true;
    }
    }
    return false;
}

void drawSamplesOnMesh(Workbench& wb, RenderPanelState& ps, const render::Settings& r,
                       float pixelScale) {
    const texspace::Pipeline* p = wb.textureSpace().pipeline();
    if (!p) return;
    const texspace::SampleSet& set = p->lastSet();
    const render::Frame& f = wb.scene().frame();
    render::Camera cam = r.camera;
    cam.aspect = float(f.width) / float(std::max(1, f.height));
    const glm::mat4 vp = cam.projection() * cam.view();
    const glm::vec3 eye = cam.position();
    const render::Readback& rb = ps.readback;
    const bool gbuffer = rb.width == f.width && rb.height == f.height && !rb.position.empty();
    ImDrawList* dl = ImGui::GetWindowDrawList();
    for (size_t i = 0; i < set.position.size(); ++i) {
        const glm::vec3 x = set.position[i];
        if (glm::dot(set.normal[i], eye - x) <= 0) continue;
        const glm::vec4 c = vp * glm::vec4(x, 1.0f);
        if (!(c.w > 0)) continue;
        const float u = (c.x / c.w * 0.5f + 0.5f) * float(f.width);
        const float v = (1.0f - (c.y / c.w * 0.5f + 0.5f)) * float(f.height);
        if (u < 0 || v < 0 || u >= float(f.width) || v >= float(f.height)) continue;
        if (gbuffer) { // hidden behind another part of the mesh?
            const glm::vec4 g = rb.position[rb.index(int(u), int(v))];
            if (g.w == 0 || glm::length(glm::vec3(g) - x) > 0.02f * cam.radius) continue;
        }
        dl->AddCircleFilled(
            ImVec2(ps.imageRect.x0 + u * pixelScale, ps.imageRect.y0 + v * pixelScale), 2.0f,
            IM_COL32(60, 255, 90, 220));
    }
}

} // namespace app
