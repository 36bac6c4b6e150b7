// Reference series (mean ± 2 standard errors) and model-vs-reference error figures.
#include "pipeline/pencil_series.h"

#include "core/color.h"

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

ModelError modelError(const plot::Series& model, const plot::Series& ref, double ld) {
    ModelError e;
    if (ref.x.empty() || model.x.empty()) return e;
    double num = 0, den = 0;
    std::vector<double> ratio(ref.x.size(), NAN);
    for (size_t i = 0; i < ref.x.size(); ++i) {
        auto rows = plot::sampleAt({model}, ref.x[i]);
        const double m = rows.empty() ? NAN : rows[0].y;
        if (!std::isfinite(m) || !std::isfinite(ref.y[i])) continue;
        num += (m - ref.y[i]) * (m - ref.y[i]);
        den += ref.y[i] * ref.y[i];
        if (ref.y[i] > 0) ratio[i] = m / ref.y[i];
    }
    if (!(den > 0)) return e;
    auto nearest = [&](double r) {
        size_t best = 0;
        for (size_t i = 1; i < ref.x.size(); ++i)
            if (std::abs(ref.x[i] - r) < std::abs(ref.x[best] - r)) best = i;
        return std::abs(ref.x[best] - r) <= (ref.x.back() - ref.x.front()) / ref.x.size()
                   ? ratio[best]
                   : NAN;
    };
    e.valid = true;
    e.relL2 = std::sqrt(num / den);
    e.ratioAt1 = nearest(ld);
    e.ratioAt4 = nearest(4 * ld);
    return e;
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

std::vector<plot::Series> plotSeries(const Workbench& wb) {
    const PlotSettings& ps = wb.plotSettings();
    std::vector<plot::Series> out;
    auto valueOf = [&](const glm::dvec3& v, int channel) {
        return channel < 3 ? v[channel] : core::luminance(v);
    };
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
            out.push_back(std::move(s));
        };
        if (!ps.solo.empty()) {
            make(0, name + " R", 0xff4040ffu);
            make(1, name + " G", 0xff40ff40u);
            make(2, name + " B", 0xffff6040u);
        } else {
            make(ps.channel, name, plot::defaultColor(slot));
            // Line styles alternate by slot (thick solid, thin dashed), so curves that coincide,
            // as dipole and better dipole do on Marble, both stay visible; like the colour, a
            // model's style does not change when others are added, removed or hidden.
            const bool odd = slot % 2 == 1;
            out.back().dashed = odd;
            out.back().thickness = odd ? 1.5f : 3.0f;
        }
    }
    if (!wb.referenceSettings().enabled) return out;
    ReferenceSnapshot snap = wb.reference().snapshot();
    if (snap.pathsDone == 0) return out;
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
    // error figures of each model that uses the reference's σ, at the plotted channel's l_d
    const ModelView* src = nullptr;
    if (auto it = wb.views().find(wb.reference().model()); it != wb.views().end())
        src = &it->second;
    for (auto& s : out) {
        for (const auto& e : wb.library().entries()) {
            auto it = wb.views().find(e.displayPath);
            if (!e.model || s.label != e.model->name || it == wb.views().end()) continue;
            const auto& mine = it->second.effective;
            const bool sameMedium =
                src && mine && src->effective && mine->sigmaA == src->effective->sigmaA &&
                mine->sigmaS == src->effective->sigmaS && mine->g == src->effective->g &&
                mine->eta == src->effective->eta;
            if (!sameMedium) {
                s.label += "  (other sigma: no error figures)";
                continue;
            }
            if (!it->second.profileProblem.empty()) {
                s.label += "  (NaN, Inf or negative values, see Errors: no error figures)";
                continue;
            }
            glm::dvec3 ld = material::diffuseMeanFreePath(*it->second.effective);
            if (snap.energyFails(ps.channel)) {
                s.label += "  (reference failed its energy check: no error figures)";
                continue;
            }
            ModelError err = modelError(s, ref, ld[ps.channel < 3 ? ps.channel : 1]);
            if (!err.valid) continue;
            char buf[160];
            std::snprintf(buf, sizeof buf, "  rel.L2 %.1f%%  ratio@1ld %.3f  @4ld %.3f",
                          100 * err.relL2, err.ratioAt1, err.ratioAt4);
            s.label += buf;
        }
    }
    for (auto& s : out)
        s.compareTo = int(out.size());
    ref.compareTo = int(out.size());
    out.push_back(std::move(ref));
    return out;
}

} // namespace app
