// sampling/gaussian_lobes: see gaussian_lobes.h.
#include "sampling/gaussian_lobes.h"

#include "core/core.h"
#include "core/text.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace sampling {
double gaussian2d(double variance, double r) {
    return std::exp(-r * r / (2 * variance)) / (2 * std::numbers::pi * variance);
}

GaussianLobes::GaussianLobes(std::vector<GaussianLobe> lobes, double eps, int channel,
                             const std::string& name)
    : m_lobes(std::move(lobes)) {
    const std::string ch = "channel " + std::to_string(channel) + ": ";
    auto fail = [&](const std::string& msg) { throw core::Error(name, 0, ch + msg); };
    if (!(eps > 0 && eps < 1))
        fail("eps must be in (0, 1) (it is " + core::formatNumber(eps, 6) + ")");
    if (m_lobes.empty()) fail("no lobes");
    double vMax = 0;
    for (size_t k = 0; k < m_lobes.size(); ++k) {
        const auto& l = m_lobes[k];
        const std::string which = "lobe " + std::to_string(k) + ": ";
        if (std::isnan(l.weight)) fail(which + "weight is NaN");
        if (std::isinf(l.weight)) fail(which + "weight is infinite");
        if (l.weight < 0)
            fail(which + "weight is negative (" + core::formatNumber(l.weight, 6) + ")");
        if (!(std::isfinite(l.variance) && l.variance > 0))
            fail(which + "variance must be finite and > 0 (it is " +
                 core::formatNumber(l.variance, 6) + ")");
        m_total += l.weight;
        if (l.weight > 0) vMax = std::max(vMax, l.variance);
    }
    if (!(m_total > 0)) fail("the profile has no energy (every weight is 0)");
    if (!std::isfinite(m_total)) fail("the profile's energy is not finite");

    // Σ w_k e^{−x/(2v_k)} − eps·W is decreasing in x = R²; at x = 2 vMax ln(1/eps) every
    // term is <= w_k·eps, so the root lies in [0, that].
    auto excess = [&](double x) {
        double s = 0;
        for (const auto& l : m_lobes)
            s += l.weight * std::exp(-x / (2 * l.variance));
        return s - eps * m_total;
    };
    double lo = 0, hi = 2 * vMax * std::log(1 / eps);
    for (int i = 0; i < 200 && hi - lo > 1e-16 * hi; ++i) {
        const double mid = 0.5 * (lo + hi);
        (excess(mid) > 0 ? lo : hi) = mid;
    }
    const double x = hi;
    m_radiusMax = std::sqrt(x);
    m_kept_k.resize(m_lobes.size());
    m_prob.resize(m_lobes.size());
    m_cumProb.resize(m_lobes.size());
    double kept = 0;
    for (size_t k = 0; k < m_lobes.size(); ++k) {
        m_kept_k[k] = -std::expm1(-x / (2 * m_lobes[k].variance));
        kept += m_lobes[k].weight * m_kept_k[k];
    }
    m_kept = kept;
    double cum = 0;
    for (size_t k = 0; k < m_lobes.size(); ++k) {
        m_prob[k] = m_lobes[k].weight * m_kept_k[k] / kept;
        cum += m_prob[k];
        m_cumProb[k] = cum;
    }
}

double GaussianLobes::sampleLobe(size_t k, double u) const {
    const double v = m_lobes[k].variance;
    const double r = std::sqrt(-2 * v * std::log1p(-std::clamp(u, 0.0, 1.0) * m_kept_k[k]));
    return std::min(r, m_radiusMax);
}

double GaussianLobes::lobeCdf(size_t k, double r) const {
    if (!(r > 0)) return 0;
    if (r >= m_radiusMax) return 1;
    return -std::expm1(-r * r / (2 * m_lobes[k].variance)) / m_kept_k[k];
}

double GaussianLobes::sample(double u) const {
    u = std::clamp(u, 0.0, 1.0);
    // Pick a lobe by u, then reuse u's position within the lobe's slot for the radius.
    size_t k = size_t(std::upper_bound(m_cumProb.begin(), m_cumProb.end(), u) - m_cumProb.begin());
    k = std::min(k, m_lobes.size() - 1);
    while (m_prob[k] == 0 && k > 0) // the last slots may be empty lobes (or rounding)
        --k;
    const double start = k == 0 ? 0.0 : m_cumProb[k - 1];
    const double local = m_prob[k] > 0 ? std::clamp((u - start) / m_prob[k], 0.0, 1.0) : 0.0;
    return sampleLobe(k, local);
}

double GaussianLobes::profile(double r) const {
    if (!(r >= 0)) return 0;
    double s = 0;
    for (const auto& l : m_lobes)
        s += l.weight * gaussian2d(l.variance, r);
    return s;
}

double GaussianLobes::pdfArea(double r) const {
    if (!(r >= 0) || r > m_radiusMax) return 0;
    return profile(r) / m_kept;
}

double GaussianLobes::cdf(double r) const {
    if (!(r > 0)) return 0;
    if (r >= m_radiusMax) return 1;
    double s = 0;
    for (size_t k = 0; k < m_lobes.size(); ++k)
        s += m_lobes[k].weight * -std::expm1(-r * r / (2 * m_lobes[k].variance));
    return std::min(s / m_kept, 1.0);
}

} // namespace sampling
