// The scores against the path-traced reference (scoring.h has the definition of each).
#include "pipeline/scoring.h"

#include "core/core.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <numbers>

namespace app {
namespace fs = std::filesystem;

std::string formatScore(double v, int digits) {
    return std::isfinite(v) ? core::formatNumber(v, digits) : "—";
}

fs::path compareCacheDir() {
    if (const char* c = std::getenv("BSSRDF_WORKBENCH_CACHE"); c && *c)
        return fs::path(c) / "reference";
    if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x)
        return fs::path(x) / "bssrdf-workbench" / "reference";
    if (const char* h = std::getenv("HOME"); h && *h)
        return fs::path(h) / ".cache" / "bssrdf-workbench" / "reference";
    return {};
}

// 2π∫₀^∞ R r dr of one channel of a model: 2048 points in ln r from 1e-6 l_d to 60 l_d,
// trapezoid in ln r (∫ R r² d ln r).
double modelTotalRd(GLuint program, const bssrdf::ModelEntry& e, const bssrdf::Builtins& b,
                    double ld, int channel) {
    const int n = 2048;
    const double a = std::log(1e-6 * ld), z = std::log(60.0 * ld), h = (z - a) / (n - 1);
    std::vector<double> radii(n);
    for (int k = 0; k < n; ++k)
        radii[k] = std::exp(a + h * k);
    const bssrdf::Profile p = bssrdf::evaluateProfile(program, *e.model, e.values, b, radii);
    double sum = 0;
    for (int k = 0; k < n; ++k) {
        const double f = p.value[k][channel] * radii[k] * radii[k];
        sum += (k == 0 || k == n - 1 ? 0.5 : 1.0) * f;
    }
    return 2 * std::numbers::pi * sum * h;
}

ScoreRow scoreAgainstReference(const std::vector<double>& rMid, const std::vector<double>& rd,
                               const std::vector<double>& rdSe, double specular, double totalRd,
                               double totalRdSe, double ldMm, const std::vector<double>& model,
                               double modelTotal) {
    ScoreRow s;
    s.ldMm = ldMm;
    const double entering = 1.0 - specular;
    const size_t n = rMid.size();
    const double dr = n > 1 ? rMid[1] - rMid[0] : 1.0;
    double num = 0, den = 0;
    std::vector<size_t> in;
    for (size_t i = 0; i < n; ++i)
        if (rMid[i] >= 0.1 * ldMm && rMid[i] <= 4.0 * ldMm) in.push_back(i);
    for (size_t i : in) {
        const double ref = rd[i] / entering, d = model[i] - ref;
        num += d * d * rMid[i] * dr;
        den += ref * ref * rMid[i] * dr;
    }
    s.relL2 = den > 0 ? std::sqrt(num / den) : std::numeric_limits<double>::infinity();
    double var = 0;
    if (num > 0 && den > 0)
        for (size_t i : in) {
            const double ref = rd[i] / entering, d = model[i] - ref;
            const double grad =
                s.relL2 / 2 * (-2 * d / num - 2 * ref / den) * rMid[i] * dr / entering;
            var += grad * grad * rdSe[i] * rdSe[i];
        }
    s.relL2Se = std::sqrt(var);
    auto ratioAt = [&](double r, double& se) {
        size_t best = 0;
        for (size_t i = 0; i < n; ++i)
            if (std::abs(rMid[i] - r) < std::abs(rMid[best] - r)) best = i;
        const double ref = rd[best] / entering;
        const double ratio = model[best] / ref;
        se = std::abs(ratio) * rdSe[best] / std::abs(rd[best]);
        return ratio;
    };
    s.ratio1 = ratioAt(ldMm, s.ratio1Se);
    s.ratio4 = ratioAt(4 * ldMm, s.ratio4Se);
    const double refTotal = totalRd / entering;
    s.totalRatio = modelTotal / refTotal;
    s.totalRatioSe = std::abs(s.totalRatio) * totalRdSe / std::abs(totalRd);
    for (size_t i : in) {
        const double ref = rd[i] / entering, d = std::abs(model[i] - ref);
        if (d > 0.05 * std::abs(ref) && d > 2 * rdSe[i] / entering) {
            s.rErr5Ld = rMid[i] / ldMm;
            break;
        }
    }
    return s;
}

void rankRows(std::vector<ScoreRow>& rows) {
    std::map<std::tuple<std::string, std::string, double>, std::vector<ScoreRow*>> groups;
    for (ScoreRow& r : rows)
        groups[{r.preset, r.channel, r.thetaI}].push_back(&r);
    for (auto& [key, g] : groups) {
        std::sort(g.begin(), g.end(),
                  [](const ScoreRow* a, const ScoreRow* b) { return a->relL2 < b->relL2; });
        // A rank group starts at its best model (the leader); a model whose rel_l2 exceeds the
        // leader's by no more than the noise, 2√(se² + se_leader²), shares the leader's rank
        // and both are marked as ties; otherwise it leads a new group at its own position.
        ScoreRow* leader = nullptr;
        for (size_t k = 0; k < g.size(); ++k) {
            ScoreRow& r = *g[k];
            r.tie = false;
            const double noise =
                leader ? 2 * std::sqrt(r.relL2Se * r.relL2Se + leader->relL2Se * leader->relL2Se)
                       : 0.0;
            if (leader && r.relL2 - leader->relL2 <= noise) {
                r.rank = leader->rank;
                r.tie = true;
                leader->tie = true;
            } else {
                r.rank = int(k) + 1;
                leader = &r;
            }
        }
    }
    std::stable_sort(rows.begin(), rows.end(), [](const ScoreRow& a, const ScoreRow& b) {
        return std::tie(a.preset, a.channel, a.thetaI, a.rank, a.relL2) <
               std::tie(b.preset, b.channel, b.thetaI, b.rank, b.relL2);
    });
}

} // namespace app
