// Irradiance panel (thesis 3.3.2, Fig. 3.3): the light of the first pass — directional with a
// shadow map and its four filters, filtered directional (projected texture), image-based
// lighting from an EXR environment (irradiance cubemap by normal), occluded IBL built
// incrementally with progress and cancel — and what it produced: the shadow map, the
// environment, the cubemap faces and the per-point irradiance statistics (the point-cloud panel
// colours points by it).
#include "gui/panels/panels.h"
#include "gui/widgets.h"

#include <algorithm>
#include <cmath>

namespace app {
namespace {

// The six 32×32 faces of the irradiance cubemap side by side (+x −x +y −y +z −z), tone mapped.
void showCubemap(GLuint cube, IrradiancePanelState& ps) {
    if (!cube) return;
    const int f = irradiance::kCubeFaceSize;
    std::vector<float> px(size_t(6 * f * f * 4));
    glGetTextureImage(cube, 0, GL_RGBA, GL_FLOAT, GLsizei(px.size() * sizeof(float)), px.data());
    float hi = 1e-6f;
    for (size_t i = 0; i < px.size(); i += 4)
        hi = std::max({hi, px[i], px[i + 1], px[i + 2]});
    std::vector<unsigned char> rgba(size_t(6 * f * f * 4));
    for (int face = 0; face < 6; ++face)
        for (int y = 0; y < f; ++y)
            for (int x = 0; x < f; ++x) {
                const size_t src = size_t(((face * f + y) * f + x) * 4);
                const size_t dst = size_t((y * 6 * f + face * f + x) * 4);
                for (int c = 0; c < 3; ++c)
                    rgba[dst + size_t(c)] =
                        (unsigned char)(255.0f *
                                        std::pow(std::clamp(px[src + size_t(c)] / hi, 0.0f, 1.0f),
                                                 1.0f / 2.2f));
                rgba[dst + 3] = 255;
            }
    gl::uploadRGBA8(ps.cubeTex, 6 * f, f, rgba.data());
    ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(ps.cubeTex.id())),
                 ImVec2(6.0f * 48, 48));
    hintText("irradiance cubemap (+x -x +y -y +z -z), max %.4g", hi);
}

} // namespace

void drawIrradiancePanel(Workbench& wb, IrradiancePanelState& ps, UiShared& ui) {
    SceneStage& scene = wb.scene();
    irradiance::Settings& l = scene.settings().light;
    using irradiance::LightMode;
    const char* modes[] = {irradiance::lightModeName(LightMode::Directional),
                           irradiance::lightModeName(LightMode::Filtered),
                           irradiance::lightModeName(LightMode::Ibl),
                           irradiance::lightModeName(LightMode::OccludedIbl)};
    int mode = int(l.mode);
    setItemWidth(200, "light");
    if (ImGui::Combo("light", &mode, modes, 4)) l.mode = irradiance::LightMode(mode);
    if (l.mode == irradiance::LightMode::Directional || l.mode == irradiance::LightMode::Filtered) {
        float dir[3] = {l.direction.x, l.direction.y, l.direction.z};
        setItemWidth(240, "towards light");
        if (ImGui::SliderFloat3("towards light", dir, -1.0f, 1.0f, "%.2f") &&
            std::abs(dir[0]) + std::abs(dir[1]) + std::abs(dir[2]) > 1e-3f)
            l.direction = {dir[0], dir[1], dir[2]};
        float e[3] = {l.irradiance.x, l.irradiance.y, l.irradiance.z};
        setItemWidth(240, "E0 (RGB)");
        if (ImGui::DragFloat3("E0 (RGB)", e, 0.01f, 0.0f, 1000.0f, "%.3g"))
            l.irradiance = glm::max(glm::vec3(e[0], e[1], e[2]), glm::vec3(0.0f));
        const char* filters[] = {"naive", "offset", "offset + PCF", "offset + PCF + jitter",
                                 "none (no shadows)"};
        int f = int(l.filter);
        setItemWidth(200, "shadow filter (Fig. 3.3)");
        if (ImGui::Combo("shadow filter (Fig. 3.3)", &f, filters, IM_ARRAYSIZE(filters)))
            l.filter = irradiance::ShadowFilter(f);
        setItemWidth(120, "shadow map");
        if (inputIntCommitted("shadow map", &l.shadowMapSize, 256))
            l.shadowMapSize = std::clamp(l.shadowMapSize, 16, 8192);
        sameLineItem(100, "offset");
        ImGui::DragFloat("offset", &l.depthOffset, 1e-4f, 0.0f, 0.1f, "%.4f");
        if (l.filter == irradiance::ShadowFilter::OffsetPcfJitter) {
            setItemWidth(120, "lookups");
            ImGui::SliderInt("lookups", &l.jitterSamples, 1, 16);
            sameLineItem(100, "radius [texels]");
            ImGui::SliderFloat("radius [texels]", &l.jitterRadius, 0.0f, 8.0f);
        }
        if (l.mode == irradiance::LightMode::Filtered) {
            setItemWidth(260, "texture (empty: checker)");
            if (pathFieldCommitted("texture (empty: checker)", ps.textureBuffer,
                                   sizeof ps.textureBuffer, scene.settings().projectedTextureFile))
                scene.reloadFiles();
        }
    } else {
        setItemWidth(260, "environment (EXR)");
        if (pathFieldCommitted("environment (EXR)", ps.envBuffer, sizeof ps.envBuffer,
                               scene.settings().environmentFile))
            scene.reloadFiles();
        setItemWidth(120, "intensity");
        ImGui::DragFloat("intensity", &l.envIntensity, 0.01f, 0.0f, 100.0f, "%.3g");
        sameLineItem(120, "rotation");
        ImGui::SliderAngle("rotation", &l.envRotation, -180.0f, 180.0f);
        if (l.mode == irradiance::LightMode::OccludedIbl) {
            setItemWidth(120, "samples");
            if (inputIntCommitted("samples", &l.occludedTotalSamples, 64))
                l.occludedTotalSamples = std::clamp(l.occludedTotalSamples, 1, 1 << 20);
            sameLineItem(100, "per frame");
            ImGui::SliderInt("per frame", &l.occludedSamplesPerStep, 1, 64);
            const int done = scene.occludedSamplesDone(), total = scene.occludedSamplesTotal();
            const std::string samples =
                std::to_string(done) + " / " + std::to_string(total) + " samples" +
                (scene.occludedRunning() || done == total ? "" : ", stopped");
            ImGui::ProgressBar(scene.occludedProgress(), ImVec2(240, 0), samples.c_str());
            if (scene.occludedRunning()) {
                sameLineIfFits(buttonWidth("stop"));
                if (ImGui::SmallButton("stop")) scene.cancelOccluded();
            }
        }
    }
    auto st = scene.stats().find("scene.irradiance");
    if (st != scene.stats().end()) {
        if (l.mode == irradiance::LightMode::OccludedIbl) {
            // progressive: each frame's step adds samples to the mean in use
            wrappedText("first pass (E_t at the points), progressive: %.1f ms for the last step of "
                        "%d samples; it starts over when the light or the points change",
                        st->second.ms, l.occludedSamplesPerStep);
            if (scene.occludedSamplesDone() >= 2) {
                const glm::vec3 rel = 100.0f * scene.occludedRelativeError();
                wrappedText("standard error: R %.2g %%, G %.2g %%, B %.2g %% of E_t (summed over "
                            "the points)",
                            rel.x, rel.y, rel.z);
            }
        } else {
            const long long runs = st->second.runs;
            wrappedText("first pass (E_t at the points): %.1f ms, run %s%s (it runs again only "
                        "when the light or the points change)",
                        st->second.ms, runs == 1 ? "once" : std::to_string(runs).c_str(),
                        runs == 1 ? "" : " times");
        }
    }
    const auto& e = scene.irradiance();
    if (!e.empty()) {
        glm::vec3 lo(1e30f), hi(-1e30f), sum(0.0f);
        for (const auto& v : e) {
            lo = glm::min(lo, v);
            hi = glm::max(hi, v);
            sum += v;
        }
        sum /= float(e.size());
        wrappedText(
            "E_t per point: min (%.3g %.3g %.3g) mean (%.3g %.3g %.3g) max (%.3g %.3g %.3g)", lo.x,
            lo.y, lo.z, sum.x, sum.y, sum.z, hi.x, hi.y, hi.z);
        if (ImGui::SmallButton("colour the point cloud by irradiance")) {
            ui.inspect.colorBy = PointColor::Irradiance;
            ui.show(PanelId::PointCloud);
        }
    }
    irradiance::Stage* stage = scene.irradianceStage();
    if (stage) {
        if (GLuint sm = stage->shadowMapTexture();
            sm && (l.mode == irradiance::LightMode::Directional ||
                   l.mode == irradiance::LightMode::Filtered ||
                   l.mode == irradiance::LightMode::OccludedIbl)) {
            // a depth view: show it grey (depth in every channel) rather than red
            glTextureParameteri(sm, GL_TEXTURE_SWIZZLE_G, GL_RED);
            glTextureParameteri(sm, GL_TEXTURE_SWIZZLE_B, GL_RED);
            ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(sm)), ImVec2(200, 200),
                         ImVec2(0, 1), ImVec2(1, 0));
            ImGui::SameLine();
            ImGui::TextDisabled("shadow map\n(depth from the light)");
        }
        if (l.mode == irradiance::LightMode::Filtered && stage->projectedTexture()) {
            ImGui::Image(
                reinterpret_cast<ImTextureID>(static_cast<intptr_t>(stage->projectedTexture())),
                ImVec2(120, 120));
            ImGui::SameLine();
            ImGui::TextDisabled("projected texture");
        }
        if (stage->environmentTexture() && (l.mode == irradiance::LightMode::Ibl ||
                                            l.mode == irradiance::LightMode::OccludedIbl)) {
            ImGui::Image(
                reinterpret_cast<ImTextureID>(static_cast<intptr_t>(stage->environmentTexture())),
                ImVec2(288, 144));
            hintText("environment (lat-long, zenith at the top)");
            showCubemap(stage->irradianceCubemap(), ps);
        }
    }
}

} // namespace app
