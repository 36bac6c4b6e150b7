// A model's evaluated radial profile checked for values that are no reflectance: NaN, ±Inf and
// negative numbers, counted per kind with the radii and channels where they occur (program.h).
#include "bssrdf/program.h"

#include "core/text.h"

#include <cmath>
#include <limits>

namespace bssrdf {

std::string profileProblem(const Profile& p) {
    struct Kind {
        const char* name;
        size_t count = 0;
        double rMin = std::numeric_limits<double>::infinity(), rMax = -rMin;
        bool channel[3] = {false, false, false};
    };
    Kind kinds[3] = {{"NaN"}, {"infinite"}, {"negative"}};
    const size_t n = std::min(p.r.size(), p.value.size());
    for (size_t i = 0; i < n; ++i) {
        bool seen[3] = {false, false, false};
        for (int c = 0; c < 3; ++c) {
            const double v = p.value[i][c];
            const int k = std::isnan(v) ? 0 : std::isinf(v) ? 1 : v < 0 ? 2 : -1;
            if (k < 0) continue;
            kinds[k].channel[c] = true;
            if (!seen[k]) {
                seen[k] = true;
                ++kinds[k].count;
                kinds[k].rMin = std::min(kinds[k].rMin, p.r[i]);
                kinds[k].rMax = std::max(kinds[k].rMax, p.r[i]);
            }
        }
    }
    std::string out;
    for (const Kind& k : kinds) {
        if (!k.count) continue;
        std::string channels;
        for (int c = 0; c < 3; ++c)
            if (k.channel[c]) channels += std::string(channels.empty() ? "" : " ") + "RGB"[c];
        out += std::string(out.empty() ? "R(r) is " : "; ") + k.name + " at " +
               std::to_string(k.count) + " of " + std::to_string(n) + " radii (r " +
               core::formatNumber(k.rMin, 4) + " to " + core::formatNumber(k.rMax, 4) +
               " mm, channel" + (channels.size() > 1 ? "s " : " ") + channels + ")";
    }
    return out;
}

} // namespace bssrdf
