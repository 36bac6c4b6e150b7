// Reference series (mean ± 2 standard errors) and the models' error figures (pencil_series.h).
#include "pipeline/pencil_series.h"

#include <algorithm>

#include "core/color.h"
#include "core/relative_error.h"
#include "core/text.h"

#include <algorithm>
#include <cmath>

namespace app {

plot::Series referenceSeries(const ReferenceSnapshot& snap, int channel, bool rTimesR) {
    plot::Series s;
    s.label = "path traced R_d/(1-R_sp) (" + std::to_string(snap.pathsDone) + " paths/channel, " +
              snap.device + ")";
    s.color = 0xffe0e0e0u;
    s.marker = true;
    s.dashed = true;
    const auto& r0 = snap.channel[0];
    if (r0.rMid.empty()) return s;
    // a reference that fails its own energy check gets no confident band
    const bool band = !snap.energyFails(channel);
    if (!band) s.label += "  energy check FAILED: no error band (see Errors)";
    for (size_t i = 0; i < r0.rMid.size(); ++i) {
        double mean = 0, var = 0;
        for (int c = 0; c < 3; ++c) {
            const auto& rc = snap.channel[c];
            const double norm = 1.0 / (1.0 - rc.specular);
            const double k = channel == 3 ? core::kRec709Luminance[c] : (channel == c ? 1.0 : 0.0);
            mean += k * rc.rd[i] * norm;
            var += k * k * rc.rdStderr[i] * rc.rdStderr[i] * norm * norm;
        }
        const double f = rTimesR ? r0.rMid[i] : 1.0;
        const double se = std::sqrt(var);
        s.x.push_back(r0.rMid[i]);
        s.y.push_back(mean * f);
        if (!band) continue;
        s.bandLo.push_back((mean - 2 * se) * f);
        s.bandHi.push_back((mean + 2 * se) * f);
    }
    return s;
}

const ScoreboardRow* scoreOf(const Workbench& wb, const std::string& displayPath, int channel) {
    for (const ScoreboardRow& r : wb.scoreboard().rows())
        if (r.displayPath == displayPath && r.channel == channel) return &r;
    return nullptr;
}

std::string errorFigures(const capture::ScoreRow& r) {
    if (!std::isfinite(r.relErr)) return "rel_err -";
    return "rel_err " + core::formatNumber(100 * r.relErr, 3) + " % +- " +
           core::formatNumber(100 * r.relErrSe, 2) + " %  ratio@1ld " +
           core::formatNumber(r.ratio1, 3) + "  @4ld " + core::formatNumber(r.ratio4, 3);
}

std::string errorTooltip(const ScoreboardRow& r) {
    const capture::ScoreRow& s = r.score;
    const double to = std::min(core::kRelErrToLd, r.coveredLd);
    return "rel_err of channel " + s.channel +
           ": the RMS relative error (model - reference) / reference over ln r in [" +
           core::formatNumber(core::kRelErrFromLd, 2) + ", " + core::formatNumber(to, 3) +
           "] l_d = [" + core::formatNumber(core::kRelErrFromLd * s.ldMm, 3) + ", " +
           core::formatNumber(to * s.ldMm, 3) + "] mm (l_d " + core::formatNumber(s.ldMm, 3) +
           " mm), the model averaged over each reference bin, the reference's own noise "
           "removed; +- its standard error. The same number as the Scoreboard and `compare`.\n"
           "ratio@1ld, @4ld: model / reference over r within 5 % of 1 and of 4 l_d." +
           (r.coveredLd < core::kRelErrToLd
                ? "\nThe plot's range reaches only " + core::formatNumber(r.coveredLd, 3) + " l_d."
                : std::string());
}

std::string normalisationNote() {
    return "Bssrdf(Xi=0, Wi=n, Xo=(r,0,0), Wo=n): R_d per unit power entering the medium [1/mm^2]";
}

std::vector<RpMarker> hybridRpMarkers(const Workbench& wb) {
    const PlotSettings& ps = wb.plotSettings();
    std::vector<RpMarker> out;
    const std::string shown = !ps.solo.empty() ? ps.solo : [&] {
        const SceneModelInput in = wb.sceneModelInput();
        return in.entry ? in.entry->displayPath : std::string();
    }();
    auto it = wb.views().find(shown);
    if (shown.empty() || it == wb.views().end() || it->second.profile.r.empty()) return out;
    const ModelView& v = it->second;
    if (ps.solo.empty() && (!v.visible || ps.channel > 2)) return out;
    const double bound = double(wb.textureSpaceSettings().sampling.local.lowerBound);
    const uint32_t colors[3] = {0xff4040ffu, 0xff40ff40u, 0xffff6040u};
    for (int c = 0; c < 3; ++c) {
        if (ps.solo.empty() && c != ps.channel) continue;
        std::vector<double> r = v.profile.r, R(r.size());
        for (size_t i = 0; i < r.size(); ++i)
            R[i] = v.profile.value[i][c];
        const double rp = texspace::findRp(r, R, bound);
        if (rp > 0)
            out.push_back(
                {rp, ps.solo.empty() ? 0xffd0d0d0u : colors[c], std::string("R_p ") + "RGB"[c]});
    }
    return out;
}

namespace {

// Why a model shown against the reference has no error figures, "" when it has them.
std::string noFiguresReason(const Workbench& wb, const ModelView& mine,
                            const ReferenceSnapshot& snap, int channel) {
    const ModelView* src = nullptr;
    if (auto it = wb.views().find(wb.reference().model()); it != wb.views().end())
        src = &it->second;
    const auto& m = mine.effective;
    const bool sameMedium = src && m && src->effective && m->sigmaA == src->effective->sigmaA &&
                            m->sigmaS == src->effective->sigmaS && m->g == src->effective->g &&
                            m->eta == src->effective->eta;
    if (!sameMedium) return "other sigma: no error figures";
    if (!mine.profileProblem.empty())
        return "NaN, Inf or negative values, see Errors: no error figures";
    if (snap.energyFails(channel)) return "reference failed its energy check: no error figures";
    return "";
}

// The legend text and tooltip of a model's error figures on `channel` (3: each of R, G, B).
void addErrorFigures(const Workbench& wb, const std::string& displayPath, const ModelView& v,
                     const ReferenceSnapshot& snap, int channel, plot::Series& s) {
    if (std::string why = noFiguresReason(wb, v, snap, channel); !why.empty()) {
        s.label += "  (" + why + ")";
        return;
    }
    if (channel < 3) {
        const ScoreboardRow* r = scoreOf(wb, displayPath, channel);
        if (!r) return; // not scored yet (or the channel has no l_d: the Scoreboard says why)
        s.label += "  " + errorFigures(r->score);
        s.tooltip = errorTooltip(*r);
        return;
    }
    std::string figures;
    for (int c = 0; c < 3; ++c) {
        const ScoreboardRow* r = scoreOf(wb, displayPath, c);
        if (!r) continue;
        figures +=
            std::string(figures.empty() ? "" : " ") + "RGB"[c] + " " +
            (std::isfinite(r->score.relErr) ? core::formatNumber(100 * r->score.relErr, 3) + " %"
                                            : std::string("-"));
        s.tooltip += (s.tooltip.empty() ? "" : "\n\n") + errorTooltip(*r);
    }
    if (!figures.empty()) s.label += "  rel_err " + figures;
}

} // namespace

namespace {

// An MCML run opened as a reference (Workbench::mcmlReference): its R_d(r)/(1 − R_sp) with the
// ±2σ band of two runs, whatever channel is plotted (it is one medium).
plot::Series mcmlSeries(const Workbench::McmlReference& m, bool rTimesR) {
    plot::Series s;
    s.label = "MCML " + m.name;
    s.color = 0xffb0b0b0u;
    s.dashed = true;
    s.marker = true;
    const pathtrace::SlabResult& p = m.profile;
    const bool band =
        std::any_of(p.rdStderr.begin(), p.rdStderr.end(), [](double v) { return v > 0; });
    for (size_t i = 0; i < p.rMid.size(); ++i) {
        const double f = (rTimesR ? p.rMid[i] : 1.0) / (1 - p.specular);
        s.x.push_back(p.rMid[i]);
        s.y.push_back(p.rd[i] * f);
        if (band) {
            s.bandLo.push_back((p.rd[i] - 2 * p.rdStderr[i]) * f);
            s.bandHi.push_back((p.rd[i] + 2 * p.rdStderr[i]) * f);
        }
    }
    s.tooltip = "MCML's R_d(r) per unit power entering, from " + m.path + " (sigma_a " +
                core::formatNumber(m.medium.sigmaA, 4) + ", sigma_s " +
                core::formatNumber(m.medium.sigmaS, 4) + " 1/mm, g " +
                core::formatNumber(m.medium.g, 3) + ", eta " + core::formatNumber(m.medium.eta, 4) +
                "): for that medium, whatever the models are evaluated with";
    return s;
}

// base: the index of the series of plot.compare_with's model, -1 when it has none.
std::vector<plot::Series> modelAndReferenceSeries(const Workbench& wb, int& base);

} // namespace

std::vector<plot::Series> plotSeries(const Workbench& wb) {
    int base = -1;
    std::vector<plot::Series> out = modelAndReferenceSeries(wb, base);
    const PlotSettings& ps = wb.plotSettings();
    if (const auto& m = wb.mcmlReference()) {
        plot::Series s = mcmlSeries(*m, ps.rTimesR);
        // compared with the path-traced reference when that is the plot's one reference
        const bool refLast = !out.empty() && out.back().compareTo == int(out.size()) - 1;
        s.compareTo = ps.solo.empty() && refLast ? int(out.size()) - 1 : -1;
        out.push_back(std::move(s));
    }
    if (base >= 0) // every curve relative to the chosen model's, references included
        for (plot::Series& s : out)
            s.compareTo = base;
    return out;
}

bool comparesWithModel(const Workbench& wb) {
    const PlotSettings& ps = wb.plotSettings();
    if (ps.compareWith.empty() || !ps.solo.empty()) return false;
    const auto it = wb.views().find(ps.compareWith);
    const auto& entries = wb.library().entries();
    const bool loaded = std::any_of(entries.begin(), entries.end(),
                                    [&](const auto& e) { return e.displayPath == ps.compareWith; });
    return loaded && it != wb.views().end() && it->second.visible && !it->second.profile.r.empty();
}

namespace {

std::vector<plot::Series> modelAndReferenceSeries(const Workbench& wb, int& base) {
    const PlotSettings& ps = wb.plotSettings();
    base = -1;
    std::vector<plot::Series> out;
    auto valueOf = [&](const glm::dvec3& v, int channel) {
        return channel < 3 ? v[channel] : core::luminance(v);
    };
    const bool withReference = wb.referenceSettings().enabled;
    const ReferenceSnapshot snap = withReference ? wb.reference().snapshot() : ReferenceSnapshot{};
    const bool scored = withReference && snap.pathsDone > 0;
    for (const auto& e : wb.library().entries()) {
        auto it = wb.views().find(e.displayPath);
        const size_t slot = wb.plotSlot(e.displayPath);
        if (it == wb.views().end() || it->second.profile.r.empty()) continue;
        const ModelView& v = it->second;
        if (!ps.solo.empty() && ps.solo != e.displayPath) continue;
        if (ps.solo.empty() && !v.visible) continue;
        const std::string name = e.model ? e.model->name : e.displayPath;
        auto make = [&](int channel, const std::string& label, uint32_t color) {
            plot::Series s;
            s.label = label;
            s.color = color;
            s.x = v.profile.r;
            s.y.resize(s.x.size());
            for (size_t i = 0; i < s.x.size(); ++i) {
                double y = valueOf(v.profile.value[i], channel);
                s.y[i] = ps.rTimesR ? y * s.x[i] : y;
            }
            if (scored) addErrorFigures(wb, e.displayPath, v, snap, channel, s);
            out.push_back(std::move(s));
        };
        if (!ps.solo.empty()) {
            make(0, name + " R", 0xff4040ffu);
            make(1, name + " G", 0xff40ff40u);
            make(2, name + " B", 0xffff6040u);
        } else {
            make(ps.channel, name, plot::defaultColor(slot));
            if (e.displayPath == ps.compareWith) base = int(out.size()) - 1;
            // Line styles alternate by slot (thick solid, thin dashed), so curves that coincide,
            // as dipole and better dipole do on Marble, both stay visible; like the colour, a
            // model's style does not change when others are added, removed or hidden.
            const bool odd = slot % 2 == 1;
            out.back().dashed = odd;
            out.back().thickness = odd ? 1.5f : 3.0f;
        }
        // a fit of this model not applied yet: its fitted curve beside it (Fit panel)
        const FitSnapshot fit = wb.fit().snapshot();
        if (ps.solo.empty() && fit.result && fit.model == e.displayPath && !fit.fitted.r.empty() &&
            fit.fittedValues != e.values) {
            plot::Series f;
            f.label = name + " fitted (Fit panel, not applied)";
            f.color = plot::defaultColor(slot);
            f.dashed = true;
            f.thickness = 1.5f;
            f.x = fit.fitted.r;
            for (size_t i = 0; i < f.x.size(); ++i) {
                const double y = valueOf(fit.fitted.value[i], ps.channel);
                f.y.push_back(ps.rTimesR ? y * f.x[i] : y);
            }
            out.push_back(std::move(f));
        }
    }
    if (!scored) return out;
    if (!ps.solo.empty()) {
        const int first = int(out.size()); // each model channel is compared with its own
        for (size_t i = 0; i < out.size(); ++i)
            out[i].compareTo = first + int(i % 3);
        for (int c = 0; c < 3; ++c) {
            plot::Series ref = referenceSeries(snap, c, ps.rTimesR);
            ref.label = std::string("path traced ") + "RGB"[c];
            ref.compareTo = first + c;
            out.push_back(std::move(ref));
        }
        return out;
    }
    plot::Series ref = referenceSeries(snap, ps.channel, ps.rTimesR);
    for (auto& s : out)
        s.compareTo = int(out.size());
    ref.compareTo = int(out.size());
    out.push_back(std::move(ref));
    return out;
}

} // namespace

} // namespace app
