// BSSRDF slice panel (seed 001): for one incidence angle, the path-traced BSSRDF of the slab
// and a model's on the same bins (slice_stage.h), as polar heatmaps over the surface plane —
// reference | model | signed relative difference — on a log colour scale with colour bars,
// R (directionally integrated) or S in one exit-direction cell; and polar plots over the exit
// directions at the selected bin. Hover or click a bin for value ± standard error. Above the
// maps, the model's rel_err over the plane and the exit directions (scoring_oblique.h).
// The plane is drawn whole: the estimate folds y → −y, so both halves show the same bins. The
// beam arrives from the left and travels toward +x (right), θs = 0 is forward.
#include "gui/panels/panels.h"
#include "gui/polar_heatmap.h"
#include "gui/widgets.h"
#include "pipeline/scoring_oblique.h"

#include "core/core.h"
#include "core/fields.h"
#include "core/relative_error.h"
#include "core/text.h"
#include "pathtrace/fresnel.h"
#include "pipeline/image_display.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <string>

namespace app {

namespace {

const ImVec4 kProblemColour(1, 0.45f, 0.45f, 1);

ImU32 rgb(const std::array<uint8_t, 3>& c) {
    return IM_COL32(c[0], c[1], c[2], 255);
}

// The exit hemisphere as a disc (radius sin θo, azimuth φo from +x): one cell per sector of
// a ring of equal solid angle. Returns the hovered cell; a click selects it.
int directionDisc(const char* id, float side, const pathtrace::BssrdfBins& b,
                  const std::function<ImU32(int)>& colour, int& selected) {
    ImDrawList* dl = ImGui::GetWindowDrawList();
    const ImVec2 p0 = ImGui::GetCursorScreenPos();
    ImGui::InvisibleButton(id, ImVec2(side, side));
    const ImVec2 c(p0.x + side * 0.5f, p0.y + side * 0.5f);
    const float R = side * 0.5f - 2.0f;
    auto ringRadius = [&](int ring) { // cos θo = ring / rings
        const float mu = float(ring) / float(b.dirCosBins);
        return R * std::sqrt(std::max(0.0f, 1.0f - mu * mu));
    };
    const float dphi = 2 * std::numbers::pi_v<float> / float(b.dirPhiBins);
    const ImDrawListFlags flags = dl->Flags;
    dl->Flags &= ~ImDrawListFlags_AntiAliasedFill;
    for (int ring = 0; ring < b.dirCosBins; ++ring)
        for (int sec = 0; sec < b.dirPhiBins; ++sec) {
            const ImU32 col = colour(ring * b.dirPhiBins + sec);
            const float r0 = ringRadius(ring + 1), r1 = ringRadius(ring);
            const int segs = std::max(1, int(std::ceil(dphi / (std::numbers::pi_v<float> / 32))));
            for (int k = 0; k < segs; ++k) {
                const float a = (float(sec) + float(k) / float(segs)) * dphi;
                const float e = (float(sec) + float(k + 1) / float(segs)) * dphi;
                auto at = [&](float r, float t) {
                    return ImVec2(c.x + r * std::cos(t), c.y - r * std::sin(t));
                };
                dl->AddQuadFilled(at(r0, a), at(r1, a), at(r1, e), at(r0, e), col);
            }
        }
    dl->Flags = flags;
    dl->AddCircle(c, R, IM_COL32(150, 150, 150, 255), 64);
    int hovered = -1;
    if (ImGui::IsItemHovered() || ImGui::IsItemClicked()) {
        const ImVec2 m = ImGui::GetMousePos();
        const float x = (m.x - c.x) / R, y = (c.y - m.y) / R, s = std::hypot(x, y);
        if (s < 1.0f) {
            const float mu = std::sqrt(1.0f - s * s);
            const double phi = std::atan2(double(y), double(x));
            hovered = pathtrace::cellOf(b, mu, phi);
        }
        if (ImGui::IsItemClicked() && hovered >= 0) selected = hovered;
    }
    if (selected >= 0 && selected < b.dirBins()) {
        const int ring = selected / b.dirPhiBins, sec = selected % b.dirPhiBins;
        const float r0 = ringRadius(ring + 1), r1 = ringRadius(ring);
        sectorOutline(dl, c, r0, r1, float(sec) * dphi, float(sec + 1) * dphi);
    }
    return hovered;
}

// Log colour scale [max·10^−decades, max].
struct LogScale {
    double hi = 1, decades = 4;
    ImU32 operator()(double v) const {
        if (!(v > 0) || !std::isfinite(v)) return IM_COL32(0, 0, 0, 255);
        const double t = 1.0 + std::log10(v / hi) / decades;
        return rgb(sequentialColor(float(t)));
    }
};

// A horizontal colour bar of `width` pixels: colour(t) for t from 0 (left) to 1 (right).
void gradientBar(float width, const std::function<ImU32(float)>& colour) {
    ImDrawList* dl = ImGui::GetWindowDrawList();
    const ImVec2 p = ImGui::GetCursorScreenPos();
    const float h = 10;
    for (int i = 0; i < 64; ++i)
        dl->AddRectFilled(ImVec2(p.x + width * float(i) / 64, p.y),
                          ImVec2(p.x + width * float(i + 1) / 64, p.y + h),
                          colour((float(i) + 0.5f) / 64));
    ImGui::Dummy(ImVec2(width, h));
}

void logColourBar(const LogScale& s, float width) {
    gradientBar(width, [](float t) { return rgb(sequentialColor(t)); });
    char lo[32], hi[32];
    std::snprintf(lo, sizeof lo, "%.3g", s.hi * std::pow(10.0, -s.decades));
    std::snprintf(hi, sizeof hi, "%.3g (log)", s.hi);
    ImGui::TextUnformatted(lo);
    // the upper end right-aligned inside the bar's width (the group stays `width` wide);
    // SameLine's offset counts from the group's start
    const float hiX = width - ImGui::CalcTextSize(hi).x;
    if (hiX > ImGui::CalcTextSize(lo).x + 8) {
        ImGui::SameLine(hiX);
        ImGui::TextUnformatted(hi);
    } else {
        ImGui::TextUnformatted(hi);
    }
}

// `text`, cut with "..." where it is wider than `width`: a map's title and legend stay within
// the map's width, so the three maps' row fits the panel.
void textWithin(const std::string& text, float width) {
    ImGui::TextUnformatted(cutToWidth(text, width).c_str());
}

void diffColourBar(float range, float width) {
    gradientBar(width, [](float t) { return rgb(divergingColor(2.0f * t - 1.0f)); });
    char legend[80];
    std::snprintf(legend, sizeof legend, "-%.0f%% model low   +%.0f%% model high",
                  double(range) * 100, double(range) * 100);
    textWithin(legend, width);
}

// Run controls: channel, θi, range, bins, paths, estimator, device; progress and cancel.
void drawControls(Workbench& wb, SlicePanelState& ps) {
    SliceSettings& s = wb.sliceSettings();
    const char* channels[] = {"R", "G", "B"};
    setItemWidth(60, "channel");
    if (ImGui::BeginCombo("channel", channels[std::clamp(s.channel, 0, 2)])) {
        for (int c = 0; c < 3; ++c)
            if (ImGui::Selectable(channels[c], s.channel == c)) s.channel = c;
        ImGui::EndCombo();
    }
    // θi and r_max apply when the edit ends (a drag restarts the run once, on release)
    if (!ps.editing[0]) ps.thetaEdit = float(s.thetaIDeg);
    sameLineItem(140, "theta_i [deg]");
    ImGui::SliderFloat("theta_i [deg]", &ps.thetaEdit, 0.0f, 89.0f, "%.1f");
    ps.editing[0] = ImGui::IsItemActive();
    if (ImGui::IsItemDeactivatedAfterEdit()) s.thetaIDeg = std::clamp(ps.thetaEdit, 0.0f, 89.9f);
    if (!ps.editing[1]) ps.rangeEdit = float(s.rangeLd);
    sameLineItem(90, "r_max [l_d]");
    ImGui::InputFloat("r_max [l_d]", &ps.rangeEdit, 0, 0, "%.3g");
    ps.editing[1] = ImGui::IsItemActive();
    if (ImGui::IsItemDeactivatedAfterEdit())
        s.rangeLd = std::clamp(double(ps.rangeEdit), 0.05, 100.0);
    sameLineItem(80, "r bins");
    if (inputIntCommitted("r bins", &s.rBins, 2)) s.rBins = std::clamp(s.rBins, 1, 200);
    sameLineIfFits(checkboxWidth("log r"));
    ImGui::Checkbox("log r", &s.logR);
    sameLineItem(80, "theta_s bins");
    if (inputIntCommitted("theta_s bins", &s.thetaSBins, 2))
        s.thetaSBins = std::clamp(s.thetaSBins, 1, 90);
    int cells[2] = {s.dirCosBins, s.dirPhiBins};
    sameLineItem(110, "exit cells");
    if (inputInt2Committed("exit cells", cells)) {
        s.dirCosBins = std::clamp(cells[0], 1, 16);
        s.dirPhiBins = std::clamp(cells[1], 1, 32);
    }
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("rings of equal solid angle x azimuth sectors");
    int tenK = int(s.paths / 10000);
    sameLineItem(100, "x1e4 paths");
    if (inputIntCommitted("x1e4 paths", &tenK, 5))
        s.paths = uint64_t(std::clamp(tenK, 1, 1000000)) * 10000;
    enumCombo("estimator", s.estimator, 110);
    enumCombo("orders", s.orders, 100);
    exitSamplesInput(s.exitSamples);
    enumCombo("device", s.device, 70);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("gpu: GL walk (shaders/bssrdf_walk.comp, hot-reloaded), a slice per "
                          "frame\ncpu: CPU walk in a background thread\nauto: the GPU where it "
                          "measured faster than the CPU here (once per run)");
    const SliceSnapshot snap = wb.slice().snapshot();
    const float frac =
        snap.pathsTarget ? float(double(snap.pathsDone) / double(snap.pathsTarget)) : 0.0f;
    char overlay[96];
    std::snprintf(overlay, sizeof overlay, "%llu / %llu paths", (unsigned long long)snap.pathsDone,
                  (unsigned long long)snap.pathsTarget);
    ImGui::ProgressBar(frac, ImVec2(fittingWidth(260), 0), overlay);
    sameLineIfFits(buttonWidth("restart"));
    if (snap.running) {
        if (ImGui::SmallButton("cancel")) wb.slice().cancel();
    } else if (ImGui::SmallButton("restart")) {
        wb.slice().restart();
    }
    sameLineIfFits(200);
    const std::string source =
        wb.slice().model().empty() ? wb.sourceModelPath() : wb.slice().model();
    hintText("%s %.3g paths/s | sigma of %s", snap.device.c_str(), snap.pathsPerSecond,
             source.c_str());
    if (const std::string choice = wb.slice().deviceChoice();
        !choice.empty() && ImGui::IsItemHovered())
        ImGui::SetTooltip("device auto, measured once at start: %s", choice.c_str());
    if (!snap.problem.empty()) colouredText(kProblemColour, "%s", snap.problem.c_str());
    if (!snap.energy.empty())
        colouredText(kProblemColour, "energy check failed: %s (no error figures)",
                     snap.energy.c_str());
}

} // namespace

void drawSlicePanel(Workbench& wb, SlicePanelState& ps, UiShared&) {
    drawControls(wb, ps);
    const SliceSnapshot snap = wb.slice().snapshot();
    const auto& models = wb.slice().models();
    // asked of the workbench, not the stage: on the frame the tab first shows, the stage has
    // not run yet and knows no model
    if (wb.sourceModelPath().empty() && models.empty()) {
        hintText("No usable model: load one in the Models panel (its sigma is the medium).");
        return;
    }
    if (!snap.slice) {
        hintText("Path tracing the first paths ...");
        return;
    }
    const pathtrace::BssrdfBins& b = snap.settings.bins;
    const pathtrace::BssrdfSlice& ref = *snap.slice;
    // the compared model
    if (!models.count(ps.model) && !models.empty()) ps.model = models.begin()->first;
    setItemWidth(220, "model");
    if (ImGui::BeginCombo("model", ps.model.c_str())) {
        for (const auto& [path, r] : models)
            if (ImGui::Selectable(path.c_str(), ps.model == path)) ps.model = path;
        ImGui::EndCombo();
    }
    sameLineItem(150, "show");
    const bool hasCells = b.dirBins() > 1 && !ref.S.empty();
    if (!hasCells) ps.quantity = SliceQuantity::R;
    const char* quantities[] = {"R (exitance)", "S (exit cell)"};
    if (ImGui::BeginCombo("show", quantities[int(ps.quantity)])) {
        if (ImGui::Selectable(quantities[0], ps.quantity == SliceQuantity::R))
            ps.quantity = SliceQuantity::R;
        if (hasCells && ImGui::Selectable(quantities[1], ps.quantity == SliceQuantity::S))
            ps.quantity = SliceQuantity::S;
        ImGui::EndCombo();
    }
    sameLineItem(90, "decades");
    ImGui::SliderFloat("decades", &ps.decades, 1.0f, 8.0f, "%.0f");
    sameLineItem(100, "diff range");
    ImGui::SliderFloat("diff range", &ps.diffRange, 0.01f, 2.0f, "%.2f");
    sameLineIfFits(checkboxWidth("grey within 2 sigma"));
    ImGui::Checkbox("grey within 2 sigma", &ps.greyTies);
    ps.cell = std::clamp(ps.cell, 0, std::max(0, b.dirBins() - 1));

    const ModelSliceResult* mr = models.count(ps.model) ? &models.at(ps.model) : nullptr;
    const ModelSlice* ms = mr && mr->slice ? &*mr->slice : nullptr;
    if (mr && !mr->problem.empty()) colouredText(kProblemColour, "%s", mr->problem.c_str());
    if (mr && (mr->medium.sigmaA != snap.medium.sigmaA || mr->medium.sigmaS != snap.medium.sigmaS ||
               mr->medium.g != snap.medium.g || mr->medium.eta != snap.medium.eta))
        hintText("note: this model has its own material; the reference uses the sigma of %s",
                 wb.slice().model().c_str());

    // values shown: R per bin, or S in the chosen cell
    const size_t bins = size_t(b.spatialBins()), cells = size_t(b.dirBins());
    std::vector<double> refV(bins), refE(bins), modV(bins, NAN);
    for (size_t i = 0; i < bins; ++i) {
        const bool s = ps.quantity == SliceQuantity::S;
        const size_t k = i * cells + size_t(ps.cell);
        refV[i] = s ? ref.S[k] : ref.R[i];
        refE[i] = s ? ref.SStderr[k] : ref.RStderr[i];
        if (ms && ms->R.size() == bins) modV[i] = s ? ms->S[k] : ms->R[i];
    }
    double hi = 0;
    for (size_t i = 0; i < bins; ++i)
        for (double v : {refV[i], modV[i]})
            if (std::isfinite(v)) hi = std::max(hi, v);
    const LogScale scale{hi > 0 ? hi : 1.0, double(ps.decades)};
    const bool trusted = snap.energy.empty();
    auto relDiff = [&](size_t i) { return (modV[i] - refV[i]) / refV[i]; };

    // the summary: rel_err over the plane (and the exit directions), as `compare` at θi > 0
    ps.summary.clear();
    if (ms && trusted && ms->R.size() == bins) {
        const pathtrace::Medium& m = snap.medium;
        const double ld = 1.0 / std::sqrt(3.0 * m.sigmaA * (m.sigmaA + m.sigmaS * (1.0 - m.g)));
        if (std::isfinite(ld) && ld > 0) {
            const capture::ScoreRow sc = scoreSlice(b, ref, *ms, ld);
            auto pct = [](double v, double se) {
                return std::isfinite(v) ? core::formatNumber(100 * v, 3) + " % +- " +
                                              core::formatNumber(100 * se, 2) + " %"
                                        : std::string("- (a bin without paths)");
            };
            ps.summary = "rel_err over the plane " + pct(sc.relErr, sc.relErrSe);
            if (sc.relErrDir)
                ps.summary +=
                    ", with the exit directions " + pct(*sc.relErrDir, sc.relErrDirSe.value_or(0));
            ps.summary += "  |  power ratio " + core::formatNumber(sc.totalRatio, 3);
            wrappedText("%s", ps.summary.c_str());
            if (ImGui::IsItemHovered()) {
                const double to = std::min(core::kRelErrToLd, b.rMaxMm / ld);
                ImGui::SetTooltip(
                    "rel_err: the RMS relative error (model - reference) / reference of R over "
                    "(ln r, theta_s), r in [%.2g, %.3g] l_d (l_d %.3g mm), each bin weighted by "
                    "its extent in ln r, the reference's noise removed; +- its standard error. "
                    "With the exit directions: of S, each cell also weighted by its projected "
                    "solid angle. The same measure as `compare --theta-i` and the Scoreboard "
                    "(pipeline/scoring_oblique.h).\npower ratio: the power the model sends "
                    "out of the plotted annulus over the reference's.",
                    core::kRelErrFromLd, to, ld);
            }
        }
    }

    const float avail = visibleWidth();
    const float gap = ImGui::GetStyle().ItemSpacing.x;
    // three in a row where they fit (a few pixels of slack for rounding), else they wrap; in a
    // row they also fit the height left (title, two colour-bar lines and the readout below), so
    // the difference map is on screen at 1280x720
    const float lineH = ImGui::GetTextLineHeightWithSpacing();
    const float byHeight = ImGui::GetContentRegionAvail().y - 5 * lineH - 10;
    const float side = std::clamp(std::min((avail - 2 * gap) / 3 - 4, byHeight), 140.0f, 420.0f);
    int hovered = -1, h = -1;
    ImGui::BeginGroup();
    ImGui::TextUnformatted("path traced");
    {
        const ImVec2 at = ImGui::GetCursorScreenPos();
        ps.refRect = {at.x, at.y, at.x + side, at.y + side};
    }
    h = polarHeatmap("##ref", side, b, {refV, [&](size_t i) { return scale(refV[i]); }}, ps.bin);
    if (h >= 0) hovered = h;
    logColourBar(scale, side);
    ImGui::EndGroup();
    sameLineIfFits(side);
    ImGui::BeginGroup();
    textWithin(mr && mr->slice ? ps.model : "model (none)", side);
    h = polarHeatmap("##model", side, b, {modV, [&](size_t i) { return scale(modV[i]); }}, ps.bin);
    if (h >= 0) hovered = h;
    logColourBar(scale, side);
    ImGui::EndGroup();
    sameLineIfFits(side);
    ImGui::BeginGroup();
    textWithin(trusted ? "(model - ref) / ref" : "difference (reference untrusted)", side);
    {
        const ImVec2 at = ImGui::GetCursorScreenPos();
        ps.diffRect = {at.x, at.y, at.x + side, at.y + side};
    }
    h = polarHeatmap("##diff", side, b,
                     {modV,
                      [&](size_t i) -> ImU32 {
                          if (!(refV[i] > 0) || !std::isfinite(modV[i]))
                              return IM_COL32(0, 0, 0, 255);
                          if (ps.greyTies && std::abs(modV[i] - refV[i]) < 2 * refE[i])
                              return IM_COL32(90, 90, 90, 255);
                          return rgb(divergingColor(float(relDiff(i)) / ps.diffRange));
                      }},
                     ps.bin);
    if (h >= 0) hovered = h;
    diffColourBar(ps.diffRange, side);
    ImGui::EndGroup();

    // readout of the hovered bin, else the selected one
    const int shown = hovered >= 0 ? hovered : ps.bin;
    const std::vector<double> edges = b.rEdges();
    if (shown >= 0 && size_t(shown) < bins) {
        const size_t i = size_t(shown);
        const int ir = shown / b.thetaSBins, it = shown % b.thetaSBins;
        const double dth = 180.0 / b.thetaSBins;
        wrappedText("r %.3g-%.3g mm, theta_s %.0f-%.0f deg: %s %.4g +- %.2g | model %.4g | "
                    "diff %+.1f%% (z %.1f)",
                    edges[size_t(ir)], edges[size_t(ir) + 1], it * dth, (it + 1) * dth,
                    ps.quantity == SliceQuantity::S ? "S" : "R", refV[i], refE[i], modV[i],
                    100 * relDiff(i), refE[i] > 0 ? (modV[i] - refV[i]) / refE[i] : 0.0);
    } else {
        hintText("Hover a bin for its value +- standard error; click to pick it for the exit "
                 "directions below.");
    }
    wrappedText("%s: R per incident photon [1/mm^2]%s, theta_i %.1f deg, %llu paths",
                core::nameOf(snap.settings.estimator),
                ps.quantity == SliceQuantity::S ? ", S [1/(mm^2 sr)] of the chosen exit cell" : "",
                snap.settings.thetaIDeg[0], (unsigned long long)snap.pathsDone);

    // exit directions at the selected bin
    if (!hasCells) {
        hintText("One exit cell: set 'exit cells' above 1x1 for S over exit directions.");
        return;
    }
    if (ps.bin < 0 || size_t(ps.bin) >= bins) {
        hintText("Click a bin to see S over the exit directions there.");
        return;
    }
    const size_t bin = size_t(ps.bin);
    double dhi = 0;
    for (size_t c = 0; c < cells; ++c) {
        dhi = std::max(dhi, ref.S[bin * cells + c]);
        if (ms && ms->S.size() == bins * cells) dhi = std::max(dhi, ms->S[bin * cells + c]);
    }
    const LogScale dscale{dhi > 0 ? dhi : 1.0, 2.0};
    const float dside = std::clamp(side * 0.6f, 100.0f, 260.0f);
    int hc = -1, hh = -1;
    ImGui::BeginGroup();
    ImGui::TextUnformatted("S, path traced");
    hh = directionDisc(
        "##dref", dside, b, [&](int c) { return dscale(ref.S[bin * cells + size_t(c)]); }, ps.cell);
    if (hh >= 0) hc = hh;
    ImGui::EndGroup();
    sameLineIfFits(dside);
    ImGui::BeginGroup();
    ImGui::TextUnformatted("S, model");
    hh = directionDisc(
        "##dmodel", dside, b,
        [&](int c) {
            return ms && ms->S.size() == bins * cells ? dscale(ms->S[bin * cells + size_t(c)])
                                                      : IM_COL32(0, 0, 0, 255);
        },
        ps.cell);
    if (hh >= 0) hc = hh;
    ImGui::EndGroup();
    sameLineIfFits(220);
    ImGui::BeginGroup();
    const int c = hc >= 0 ? hc : ps.cell;
    const size_t k = bin * cells + size_t(c);
    const int ring = c / b.dirPhiBins, sec = c % b.dirPhiBins;
    const double mu0 = double(ring) / b.dirCosBins, mu1 = double(ring + 1) / b.dirCosBins;
    wrappedText("exit cell %d: theta_o %.0f-%.0f deg, phi_o %.0f-%.0f deg", c,
                std::acos(mu1) * 180 / std::numbers::pi, std::acos(mu0) * 180 / std::numbers::pi,
                sec * 360.0 / b.dirPhiBins, (sec + 1) * 360.0 / b.dirPhiBins);
    ImGui::Text("S path traced %.4g +- %.2g", ref.S[k], ref.SStderr[k]);
    if (ms && ms->S.size() == bins * cells) ImGui::Text("S model       %.4g", ms->S[k]);
    hintText("disc: radius sin(theta_o), phi_o from +x (the beam's direction); colour log, 2 "
             "decades. Click a cell to show S there on the plane.");
    ImGui::EndGroup();
}

} // namespace app
