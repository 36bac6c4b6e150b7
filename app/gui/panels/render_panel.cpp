// Render panel (thesis 3.3.3, 3.6.4): the mesh rendered with the selected model by the
// hierarchical octree traversal (or brute force), HDR exposure and gamma, the ε of the
// solid-angle criterion or its bounding-box variant, and heatmaps of the traversal — nodes
// visited per pixel, maximum stack depth, relative error against brute force. Drag to orbit,
// wheel to zoom (half resolution while moving); click a pixel to trace it in the debugger.
#include "core/core.h"
#include "gui/export_buttons.h"
#include "gui/panels/panels.h"
#include "gui/widgets.h"

#include "pathtrace/image_io.h"
#include "pipeline/image_display.h"
#include "render/frame_analysis.h"

#include <algorithm>
#include <cmath>

namespace app {
namespace fs = std::filesystem;
namespace {

// RGBA8 image of a heatmap quantity (render::heatValues): the colour ramp over [0, max], grey
// where there is no value, magenta where the traversal flagged the pixel (stack overflow,
// iteration cap, loop limit).
std::vector<unsigned char> heatImage(const render::Readback& rb, const std::vector<float>& v,
                                     float maxValue) {
    std::vector<unsigned char> rgba(v.size() * 4, 0);
    for (size_t p = 0; p < v.size(); ++p) {
        glm::vec3 c =
            v[p] < 0 ? glm::vec3(0.12f) : core::colorRamp(maxValue > 0 ? v[p] / maxValue : 0);
        if (rb.stats[p].z != 0) c = {1.0f, 0.0f, 1.0f};
        rgba[4 * p] = (unsigned char)(c.x * 255);
        rgba[4 * p + 1] = (unsigned char)(c.y * 255);
        rgba[4 * p + 2] = (unsigned char)(c.z * 255);
        rgba[4 * p + 3] = 255;
    }
    return rgba;
}

// A/B: the brute-force image of the same view over the part of the image right of the
// divider, and a strip under the image to drag the divider.
bool drawAbSplit(Workbench& wb, RenderPanelState& ps) {
    SceneStage& scene = wb.scene();
    const SceneComparison& comparison = scene.comparison();
    // the B side: current, and of the kind chosen (else asked for again)
    const std::string wantName =
        ps.abWith.empty() ? "brute force"
                          : (wb.library().find(ps.abWith) && wb.library().find(ps.abWith)->model
                                 ? wb.library().find(ps.abWith)->model->name
                                 : ps.abWith);
    const std::vector<unsigned char>* brute =
        comparison.name() == wantName ? comparison.image() : nullptr;
    const Rect r = ps.imageRect;
    ImDrawList* dl = ImGui::GetWindowDrawList();
    const float xs = r.x0 + ps.split * r.width();
    // each side's label within its side: a long model name is cut with "...", never under
    // the other label
    ps.abLabels[0] = ps.abLabels[1] = Rect{};
    const auto label = [&](int side, const std::string& text, ImU32 colour) {
        const float x0 = side == 0 ? r.x0 + 4 : xs + 4, x1 = side == 0 ? xs - 4 : r.x1 - 4;
        if (x1 - x0 < ImGui::CalcTextSize("A: ...").x) return; // the divider at the edge
        const std::string shown = cutToWidth(text, x1 - x0);
        const ImVec2 size = ImGui::CalcTextSize(shown.c_str());
        dl->AddText(ImVec2(x0, r.y0 + 2), colour, shown.c_str());
        ps.abLabels[side] = {x0, r.y0 + 2, x0 + size.x, r.y0 + 2 + size.y};
    };
    if (brute) {
        const render::Frame& f = scene.frame();
        const auto st = scene.stats().find("scene.render");
        const long long runs = st != scene.stats().end() ? st->second.runs : 0;
        if (ps.abFrame != runs || !ps.abTex.id()) {
            gl::uploadRGBA8(ps.abTex, f.width, f.height, brute->data());
            ps.abFrame = runs;
        }
        dl->AddImage(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(ps.abTex.id())),
                     ImVec2(xs, r.y0), ImVec2(r.x1, r.y1), ImVec2(ps.split, 0), ImVec2(1, 1));
        label(1, "B: " + wantName, IM_COL32(255, 255, 255, 255));
    } else if (comparison.running()) {
        label(1, "B: " + comparison.name() + " ...", IM_COL32(255, 200, 80, 255));
    } else if (!scene.rendering()) {
        try {
            wb.requestSceneComparison(ps.abWith); // the B side of this view
        } catch (const std::exception& e) {
            wb.reportActionError(e.what());
            ps.abSplit = false;
        }
    }
    const SceneModelInput a = wb.sceneModelInput();
    label(0, "A: " + (a.entry && a.entry->model ? a.entry->model->name : std::string("?")),
          IM_COL32(255, 255, 255, 255));
    dl->AddLine(ImVec2(xs, r.y0), ImVec2(xs, r.y1), IM_COL32(255, 255, 0, 255), 2.0f);
    // the divider's handle: a strip under the image, dragged sideways
    const ImVec2 keep = ImGui::GetCursorScreenPos();
    ImGui::SetCursorScreenPos(ImVec2(r.x0, r.y1 + 1));
    ImGui::InvisibleButton("##divider", ImVec2(std::max(1.0f, r.width()), 10));
    const bool active = ImGui::IsItemActive();
    if (ImGui::IsItemHovered() || active) ImGui::SetMouseCursor(ImGuiMouseCursor_ResizeEW);
    if (active)
        ps.split =
            std::clamp((ImGui::GetIO().MousePos.x - r.x0) / std::max(1.0f, r.width()), 0.0f, 1.0f);
    dl->AddRectFilled(ImVec2(xs - 6, r.y1 + 1), ImVec2(xs + 6, r.y1 + 11),
                      IM_COL32(255, 255, 0, active ? 255 : 160));
    ImGui::SetCursorScreenPos(ImVec2(keep.x, std::max(keep.y, r.y1 + 12)));
    return active;
}

// The model the Render panel renders: a usable model chosen by name, or the first visible.
void drawModelChoice(Workbench& wb, std::string& chosen) {
    const SceneModelInput in = wb.sceneModelInput();
    const std::string shown = in.entry ? in.entry->displayPath : "(no usable model)";
    setItemWidth(220, "model");
    const std::string preview = chosen.empty() ? "first visible: " + shown : shown;
    const bool open = ImGui::BeginCombo("model", preview.c_str());
    if (!open && ImGui::IsItemHovered()) ImGui::SetTooltip("renders %s", preview.c_str());
    if (open) {
        if (ImGui::Selectable("(the first visible model)", chosen.empty())) chosen.clear();
        for (const auto& e : wb.library().entries()) {
            if (!e.usable()) continue;
            if (ImGui::Selectable(e.displayPath.c_str(), chosen == e.displayPath))
                chosen = e.displayPath;
        }
        ImGui::EndCombo();
    }
    if (!chosen.empty() && (!in.entry || in.entry->displayPath != chosen)) {
        sameLineIfFits(200);
        hintText("%s is not usable: showing %s", chosen.c_str(), shown.c_str());
    }
}

ImVec2 uvUnderMouse(const Rect& r) {
    const ImVec2 m = ImGui::GetMousePos();
    return ImVec2((m.x - r.x0) / std::max(1.0f, r.width()),
                  (m.y - r.y0) / std::max(1.0f, r.height()));
}

// Hovering the image: a magnified 9 × 9 pixel neighbourhood and the pixel's values.
void probePixel(SceneStage& scene, RenderPanelState& ps, ImVec2 uv) {
    const render::Readback* rb = shownReadback(scene, ps);
    if (!rb) return;
    const int x = std::clamp(int(uv.x * float(rb->width)), 0, rb->width - 1);
    const int y = std::clamp(int(uv.y * float(rb->height)), 0, rb->height - 1);
    // another renderer's image over the frame: its colours, and its estimate first
    const RenderPanelState::ShownImage& shown = ps.shown;
    const bool over = shown.width == rb->width && shown.height == rb->height &&
                      shown.rgba.size() == 4 * rb->hdr.size();
    const bool estimate = over && shown.hdr && shown.hdr->mean.size() == 3 * rb->hdr.size() &&
                          shown.hdr->variance.size() == shown.hdr->mean.size();
    ImGui::BeginTooltip();
    constexpr int kHalf = 4;
    constexpr float kCell = 12.0f;
    const ImVec2 o = ImGui::GetCursorScreenPos();
    ImDrawList* dl = ImGui::GetWindowDrawList();
    for (int dy = -kHalf; dy <= kHalf; ++dy)
        for (int dx = -kHalf; dx <= kHalf; ++dx) {
            const int xx = x + dx, yy = y + dy;
            const ImVec2 a(o.x + float(dx + kHalf) * kCell, o.y + float(dy + kHalf) * kCell);
            ImU32 col = IM_COL32(40, 40, 40, 255);
            if (xx >= 0 && yy >= 0 && xx < rb->width && yy < rb->height) {
                const size_t q = 4 * rb->index(xx, yy);
                const unsigned char* c = over ? &shown.rgba[q] : &rb->ldr[q];
                col = IM_COL32(c[0], c[1], c[2], 255);
            }
            dl->AddRectFilled(a, ImVec2(a.x + kCell, a.y + kCell), col);
        }
    const ImVec2 c(o.x + kHalf * kCell, o.y + kHalf * kCell);
    dl->AddRect(c, ImVec2(c.x + kCell, c.y + kCell), IM_COL32(255, 0, 255, 255));
    ImGui::Dummy(ImVec2((2 * kHalf + 1) * kCell, (2 * kHalf + 1) * kCell));
    const size_t p = rb->index(x, y);
    ImGui::Text("pixel (%d, %d) of %dx%d", x, y, rb->width, rb->height);
    if (estimate && rb->position[p].w > 0.5f) {
        const float* m = &shown.hdr->mean[3 * p];
        const float* v = &shown.hdr->variance[3 * p];
        ImGui::Text("%s", shown.what.c_str());
        ImGui::Text("L_o  %.5g %.5g %.5g", m[0], m[1], m[2]);
        ImGui::Text(" +-  %.2g %.2g %.2g (standard error)", std::sqrt(std::max(v[0], 0.0f)),
                    std::sqrt(std::max(v[1], 0.0f)), std::sqrt(std::max(v[2], 0.0f)));
        ImGui::TextDisabled("the %s frame's:",
                            scene.settings().render.bruteForce ? "brute-force" : "hierarchical");
    }
    if (rb->position[p].w > 0.5f) {
        ImGui::Text("L_o  %.5g %.5g %.5g", rb->hdr[p].x, rb->hdr[p].y, rb->hdr[p].z);
        ImGui::Text("M    %.5g %.5g %.5g", rb->exitance[p].x, rb->exitance[p].y, rb->exitance[p].z);
        ImGui::Text("steps %u, max stack %u%s", rb->stats[p].x, rb->stats[p].y,
                    rb->stats[p].z ? ", FLAGGED" : "");
    } else {
        ImGui::TextDisabled("background");
    }
    ImGui::EndTooltip();
}

// Export of the shown frame: the name field and the two buttons, each asking where (the file
// dialog, in the folder of the last export); the full path written goes to the status line and
// the log.
void drawExport(Workbench& wb, RenderPanelState& ps, UiShared& ui) {
    std::vector<std::array<float, 4>> rects;
    const auto chosen = drawExportButtons("Export render", ps.exportName, sizeof ps.exportName,
                                          {".exr", ".png"}, ps.exporter, &rects);
    for (size_t i = 0; i < rects.size() && i < 2; ++i)
        ps.exportButtons[i] = {rects[i][0], rects[i][1], rects[i][2], rects[i][3]};
    if (!chosen) return;
    try {
        exportRenderView(wb, ps, *chosen);
        ui.status = "wrote " + chosen->string();
        core::logInfo("render: wrote " + chosen->string());
    } catch (const core::Error& e) {
        wb.reportActionError(std::string("export render: ") + e.what());
    }
}

} // namespace

const render::Readback* shownReadback(SceneStage& scene, RenderPanelState& ps) {
    if (scene.rendering()) return nullptr; // the renderer holds a frame in progress
    const auto st = scene.stats().find("scene.render");
    const long long runs = st != scene.stats().end() ? st->second.runs : 0;
    if (ps.readbackRuns != runs || ps.readback.width == 0) {
        ps.readback = scene.readback();
        ps.readbackRuns = runs;
    }
    return ps.readback.width > 0 ? &ps.readback : nullptr;
}

GLuint showEstimate(SceneStage& scene, RenderPanelState& ps, const std::string& what,
                    const pathtrace::Image& img, gl::Texture& tex) {
    const render::Settings& r = scene.settings().render;
    RenderPanelState::ShownImage& shown = ps.shown;
    shown.what = what;
    shown.width = img.width;
    shown.height = img.height;
    shown.rgba = tonemap(img, r.exposure, r.gamma);
    if (const render::Readback* rb = shownReadback(scene, ps);
        rb && rb->width == img.width && rb->height == img.height)
        paintMisses(shown.rgba, rb->hdr, r.background);
    shown.hdr = img;
    gl::uploadRGBA8(tex, img.width, img.height, shown.rgba.data());
    return tex.id();
}

void exportRenderView(Workbench& wb, RenderPanelState& ps, const std::filesystem::path& path) {
    const std::string ext = path.extension().string();
    if (ext != ".exr" && ext != ".png")
        throw core::Error(path.string(), 0, "the view exports as .exr or .png, not '" + ext + "'");
    if (const RenderPanelState::ShownImage& shown = ps.shown; shown.width > 0) {
        if (ext == ".png")
            gl::writePng(path, shown.width, shown.height, shown.rgba);
        else if (shown.hdr)
            pathtrace::writeExr(path, *shown.hdr);
        else
            throw core::Error(path.string(), 0,
                              "the shown " + shown.what + " is a colour map: it exports as .png");
        return;
    }
    const render::Readback* rb = shownReadback(wb.scene(), ps);
    if (!rb) throw core::Error(path.string(), 0, "no finished frame to export yet");
    if (ext == ".exr")
        pathtrace::writeExr(path, hdrImage(*rb));
    else
        gl::writePng(path, rb->width, rb->height, rb->ldr);
}

void drawRenderPanel(Workbench& wb, RenderPanelState& ps, UiShared& ui) {
    SceneStage& scene = wb.scene();
    render::Settings& r = scene.settings().render;
    drawModelChoice(wb, scene.settings().model);
    bool& hybrid = wb.textureSpaceSettings().sampling.hybrid;
    int renderer = ps.mode == RenderMode::MonteCarlo     ? 2
                   : ps.mode == RenderMode::TextureSpace ? (hybrid ? 4 : 3)
                                                         : (r.bruteForce ? 1 : 0);
    sameLineItem(220, "renderer");
    if (ImGui::Combo("renderer", &renderer,
                     "hierarchical\0brute force\0Monte Carlo (probe rays)\0texture space\0hybrid "
                     "(local + global)\0")) {
        r.bruteForce = renderer == 1;
        ps.mode = renderer == 2   ? RenderMode::MonteCarlo
                  : renderer >= 3 ? RenderMode::TextureSpace
                                  : RenderMode::PointCloud;
        hybrid = renderer == 4;
    }
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("hierarchical / brute force: the point cloud (thesis 3.3)\nMonte "
                          "Carlo: entry points by probe rays (King et al. 2013) with shadow rays, "
                          "on the finished frame's view, progressive\ntexture space: N texels "
                          "drawn by the irradiance-weighted mip CDF (Chang 2007), one set shared "
                          "by every pixel, progressive over sets\nhybrid: R_d split at R_p into "
                          "a local part (light-view map, ring filter) and a global part (texture "
                          "space)");
    // The octree's settings: brute force evaluates every point and has none.
    const bool bruteForce = ps.mode == RenderMode::PointCloud && r.bruteForce;
    auto octreeOnly = [bruteForce](const char* tip) {
        if (!ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) return;
        if (bruteForce)
            ImGui::SetTooltip("the hierarchical renderer's (brute force evaluates every point)");
        else if (tip)
            ImGui::SetTooltip("%s", tip);
    };
    ImGui::BeginDisabled(bruteForce);
    setItemWidth(160, "eps");
    ImGui::SliderFloat("eps", &r.eps, 0.001f, 20.0f, "%.4f", ImGuiSliderFlags_Logarithmic);
    octreeOnly("the criterion's threshold: a node is accepted when A / d^2 < eps, d the "
               "distance to its mean position, or to its box with the bounding-box criterion "
               "(defaults 0.05 and 4)");
    sameLineIfFits(checkboxWidth("bounding-box criterion"));
    ImGui::Checkbox("bounding-box criterion", &r.boundingBoxCriterion);
    octreeOnly(nullptr);
    sameLineIfFits(checkboxWidth("2nd-order clusters"));
    ImGui::Checkbox("2nd-order clusters", &r.secondOrder);
    octreeOnly("an accepted node is evaluated at three points that match its "
               "irradiance-weighted covariance (exact to second order) instead of at its mean "
               "position");
    ImGui::EndDisabled();
    setItemWidth(120, "exposure");
    ImGui::SliderFloat("exposure", &r.exposure, -10.0f, 10.0f, "%.1f EV");
    sameLineItem(100, "gamma");
    ImGui::SliderFloat("gamma", &r.gamma, 0.5f, 4.0f, "%.2f");
    sameLineIfFits(checkboxWidth("direct Bssrdf()"));
    ImGui::Checkbox("direct Bssrdf()", &r.directBssrdf);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip(
            "radial models: call Bssrdf() per evaluation instead of the profile table");
    int size[2] = {r.width, r.height};
    setItemWidth(140, "size");
    if (inputInt2Committed("size", size)) {
        r.width = std::clamp(size[0], 16, 4096);
        r.height = std::clamp(size[1], 16, 4096);
    }
    sameLineIfFits(checkboxWidth("half resolution while moving"));
    ImGui::Checkbox("half resolution while moving", &scene.settings().halfResolutionWhileChanging);
    const char* heat[] = {"image", "nodes visited", "max stack depth", "rel. error vs brute force"};
    setItemWidth(200, "show");
    comboEnum("show", ps.heatmap, heat);
    sameLineIfFits(checkboxWidth("A/B") + 200);
    ImGui::Checkbox("A/B", &ps.abSplit);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("left of the divider this render, right of it B: brute force (every "
                          "point) or another model, same view; drag the strip under the image");
    if (ps.abSplit) {
        ImGui::SameLine();
        setItemWidth(180, "B");
        if (ImGui::BeginCombo("B", ps.abWith.empty() ? "brute force" : ps.abWith.c_str())) {
            if (ImGui::Selectable("brute force", ps.abWith.empty())) ps.abWith.clear();
            for (const auto& e : wb.library().entries())
                if (e.usable() &&
                    ImGui::Selectable(e.displayPath.c_str(), ps.abWith == e.displayPath))
                    ps.abWith = e.displayPath;
            ImGui::EndCombo();
        }
    }

    const render::Frame& f = scene.frame();
    if (!scene.hasFrame()) {
        hintText(scene.generating() ? "waiting for the point cloud ..."
                                    : "nothing rendered yet (needs a usable model, a "
                                      "mesh and its point cloud)");
        return;
    }
    auto st = scene.stats().find("scene.render");
    // One line, so the image does not move under the cursor when the numbers change; the
    // breakdown is in its tooltip.
    const long long renders = st != scene.stats().end() ? st->second.runs : 0;
    ImGui::Text("%dx%d | %.1f ms | %lld renders", f.width, f.height,
                f.gbufferMs + f.profileMs + f.traverseMs + f.tonemapMs, renders);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("%dx%d frame\nG-buffer %.1f ms\nprofile %.1f ms\ntraversal %.1f ms (%d "
                          "dispatches, %d band(s) of rows)\ntone map %.1f ms\n%lld renders so far",
                          f.width, f.height, f.gbufferMs, f.profileMs, f.traverseMs, f.dispatches,
                          f.bands, f.tonemapMs, renders);
    GLuint tex = f.ldr;
    ps.shown.width = 0; // the frame's own, unless a view below shows another image
    if (ps.mode == RenderMode::MonteCarlo) {
        MonteCarloSettings& mc = wb.monteCarloSettings();
        samplingChoice("sampling", mc.sampling, mc.axes);
        sameLineItem(100, "spp");
        if (inputIntCommitted("spp", &mc.spp, 64)) mc.spp = std::clamp(mc.spp, 1, 10000000);
        const MonteCarloStage& m = wb.monteCarlo();
        if (!m.problem().empty()) {
            colouredText(ImVec4(1, 0.45f, 0.45f, 1), "%s", m.problem().c_str());
        } else if (m.active()) {
            const litsphere::Image img = m.image();
            double var = 0, sum2 = 0;
            for (size_t i = 0; i < img.mean.size(); ++i)
                if (std::isfinite(img.variance[i])) {
                    var += img.variance[i];
                    sum2 += double(img.mean[i]) * img.mean[i];
                }
            wrappedText("Monte Carlo %llu / %d spp, %.1f s, relative standard error %.3g",
                        (unsigned long long)m.sppDone(), mc.spp, m.seconds(),
                        sum2 > 0 ? std::sqrt(var / sum2) : 0.0);
            if (img.width == f.width && img.height == f.height)
                tex = showEstimate(scene, ps, "Monte Carlo render", img, ps.mcTex);
        } else {
            hintText("waiting for the full-resolution frame ...");
        }
    }
    if (ps.mode == RenderMode::TextureSpace && drawTextureSpaceView(wb, ps, f, tex)) return;
    if (ps.heatmap != Heatmap::Image) {
        // the shown frame's read-back once per frame rendered (a frame in progress: each time)
        const render::Readback* done = shownReadback(scene, ps);
        const render::Readback inProgress = done ? render::Readback{} : scene.readback();
        const render::Readback& rb = done ? *done : inProgress;
        const std::vector<glm::vec4>* brute = scene.comparison().bruteForceResult();
        if (ps.heatmap == Heatmap::RelativeError && !brute) {
            if (scene.comparison().running()) {
                colouredText(ImVec4(1, 0.8f, 0.3f, 1), "brute force running ...");
            } else if (scene.rendering()) {
                ImGui::TextDisabled("waiting for the frame to finish");
            } else if (ImGui::Button("compute brute force for this view")) {
                try {
                    scene.comparison().requestBruteForce();
                } catch (const std::exception& e) {
                    wb.reportActionError(e.what());
                }
            }
        }
        if (ps.heatmap != Heatmap::RelativeError ||
            (brute && brute->size() == rb.exitance.size())) {
            static const std::vector<glm::vec4> kNone;
            const auto q = static_cast<render::HeatQuantity>(static_cast<int>(ps.heatmap) - 1);
            std::vector<unsigned char> rgba = heatImage(
                rb, render::heatValues(rb, q, brute ? *brute : kNone, ps.heatMax), ps.heatMax);
            gl::uploadRGBA8(ps.heatTex, rb.width, rb.height, rgba.data());
            tex = ps.heatTex.id();
            ps.shown = {ps.heatmap == Heatmap::Steps        ? "traversal steps heatmap"
                        : ps.heatmap == Heatmap::StackDepth ? "stack depth heatmap"
                                                            : "relative error heatmap",
                        rb.width, rb.height, std::move(rgba), std::nullopt};
            rampBar(0, ps.heatMax,
                    ps.heatmap == Heatmap::RelativeError ? "(magenta: flagged pixel)"
                                                         : "(magenta: flagged)");
        }
    }
    // (widths from visibleWidth: the same with or without the vertical scrollbar, so a size that
    // needs the scrollbar only at the wider width cannot make the panel flip between the two)
    const ImVec2 avail(visibleWidth(), ImGui::GetContentRegionAvail().y);
    const float width = std::max(160.0f, std::min(avail.x, (avail.y - 24.0f) * float(f.width) /
                                                               float(std::max(f.height, 1))));
    int px = -1, py = -1;
    ImVec2 drag, uv;
    float wheel = 0;
    if (pickImage("##render", tex, f.width, f.height, width, px, py, false, &drag, &wheel, &uv)) {
        ui.inspect.pendingPick = std::pair{uv.x, uv.y};
        ui.inspect.debugProblem.clear();
    }
    {
        const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
        ps.imageRect = {a.x, a.y, b.x, b.y};
    }
    const bool imageHeld = ImGui::IsItemActive();
    // moving the divider changes nothing to render (no half-resolution frame)
    const bool dividerHeld = ps.abSplit && ps.heatmap == Heatmap::Image && drawAbSplit(wb, ps);
    if (ImGui::IsItemHovered() && !imageHeld) probePixel(scene, ps, uvUnderMouse(ps.imageRect));
    const bool moving = drag.x != 0 || drag.y != 0 || wheel != 0;
    if (moving) {
        r.camera.yaw -= drag.x * 0.01f;
        r.camera.pitch = std::clamp(r.camera.pitch + drag.y * 0.01f, -1.5f, 1.5f);
        if (wheel != 0)
            r.camera.distance = std::max(0.05f, r.camera.distance * std::pow(0.9f, wheel));
    }
    // Interacting (half resolution when enabled): orbiting, zooming or dragging a control; a
    // press on the image that does not drag is a click, typing is not an interaction, and
    // neither is holding a button (Export, Save), which changes nothing to render: a held
    // button once restarted the frame, so a click on Save found no finished frame to export.
    const bool dragged = ImGui::IsMouseDragging(ImGuiMouseButton_Left, 2.0f);
    const bool dragging = imageHeld && dragged;
    const bool typing = ImGui::GetIO().WantTextInput; // a text field edits nothing yet
    wb.setInteracting(
        moving || dragging ||
        (ImGui::IsAnyItemActive() && dragged && !imageHeld && !typing && !dividerHeld));
    // A click is traced on the finished full-resolution frame, wherever the click was made; the
    // traced pixel is traced again on every new such frame (SceneInspect::follow).
    const bool frameDone =
        f.width == r.width && f.height == r.height && !scene.rendering() && !imageHeld;
    const auto stat = scene.stats().find("scene.render");
    const long long frameCount = stat == scene.stats().end() ? 0 : stat->second.runs;
    if (ui.inspect.pendingPick) {
        if (frameDone) {
            const auto [u, v] = *ui.inspect.pendingPick;
            ui.inspect.pendingPick.reset();
            ui.inspect.tracedFrame = frameCount;
            ui.inspect.previous.reset();
            try {
                ui.inspect.debug =
                    scene.debugPixel(std::clamp(int(u * float(f.width)), 0, f.width - 1),
                                     std::clamp(int(v * float(f.height)), 0, f.height - 1));
                ui.inspect.debugProblem.clear();
                ui.show(PanelId::Traversal);
            } catch (const std::exception& e) {
                ui.inspect.debugProblem = e.what();
            }
        } else {
            hintText("tracing the clicked pixel when the full-resolution frame is done ...");
        }
    } else if (ui.inspect.debug && ui.inspect.follow && frameDone &&
               frameCount != ui.inspect.tracedFrame) {
        ui.inspect.tracedFrame = frameCount;
        try {
            PixelDebug again = scene.debugPixel(ui.inspect.debug->x, ui.inspect.debug->y);
            ui.inspect.previous = std::move(ui.inspect.debug);
            ui.inspect.debug = std::move(again);
            ui.inspect.debugProblem.clear();
        } catch (const std::exception& e) { // the frame is smaller now: the pixel is gone
            ui.inspect.debugProblem = e.what();
        }
    }
    if (ui.inspect.debug && ui.inspect.debug->hit) {
        const float s = width / float(f.width);
        const ImVec2 o(ps.imageRect.x0, ps.imageRect.y0);
        ImGui::GetWindowDrawList()->AddRect(
            ImVec2(o.x + float(ui.inspect.debug->x) * s, o.y + float(ui.inspect.debug->y) * s),
            ImVec2(o.x + float(ui.inspect.debug->x + 1) * s + 2,
                   o.y + float(ui.inspect.debug->y + 1) * s + 2),
            IM_COL32(255, 0, 255, 255));
    }
    if (ps.mode == RenderMode::TextureSpace && ps.tsSamplesOnMesh)
        drawSamplesOnMesh(wb, ps, r, width / float(f.width));
    if (!ui.inspect.debugProblem.empty())
        colouredText(ImVec4(1, 0.45f, 0.45f, 1), "%s", ui.inspect.debugProblem.c_str());
    hintText("drag: orbit, wheel: zoom, hover: pixel zoom and values, click: trace a pixel");
    drawExport(wb, ps, ui);
}

} // namespace app
