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

} // namespace app
