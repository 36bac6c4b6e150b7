// sampling/tabulated_radial: see tabulated_radial.h.
#include "sampling/tabulated_radial.h"

#include "core/core.h"
#include "core/text.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace sampling {
TabulatedRadial::TabulatedRadial(std::vector<double> radii, std::vector<double> values, double eps,
                                 int channel, const std::string& name)
    : m_radii(std::move(radii)), m_values(std::move(values)), m_eps(eps) {
    const std::string ch = "channel " + std::to_string(channel) + ": ";
    auto fail = [&](const std::string& msg) { throw core::Error(name, 0, ch + msg); };
    if (!(eps > 0 && eps < 1))
        fail("eps must be in (0, 1) (it is " + core::formatNumber(eps, 6) + ")");
    if (m_radii.size() < 2)
        fail("the table needs at least 2 radii (it has " + std::to_string(m_radii.size()) + ")");
    if (m_radii.size() != m_values.size())
        fail("radii and values differ in length (" + std::to_string(m_radii.size()) + " and " +
             std::to_string(m_values.size()) + ")");
    if (m_radii[0] != 0)
        fail("the first radius must be 0 (it is " + core::formatNumber(m_radii[0], 6) + ")");
    for (size_t k = 1; k < m_radii.size(); ++k) {
        if (!std::isfinite(m_radii[k]))
            fail("radius " + std::to_string(k) + " is not finite (" +
                 core::formatNumber(m_radii[k], 6) + ")");
        if (!(m_radii[k] > m_radii[k - 1]))
            fail("radii must increase strictly (entry " + std::to_string(k) + ": " +
                 core::formatNumber(m_radii[k], 6) + " after " +
                 core::formatNumber(m_radii[k - 1], 6) + ")");
    }
    for (size_t k = 0; k < m_values.size(); ++k) {
        const double v = m_values[k];
        const std::string at = " at r = " + core::formatNumber(m_radii[k], 6) + " mm (entry " +
                               std::to_string(k) + ")";
        if (std::isnan(v)) fail("R(r) is NaN" + at);
        if (std::isinf(v)) fail("R(r) is infinite" + at);
        if (v < 0) fail("R(r) is negative (" + core::formatNumber(v, 6) + ")" + at);
    }

    const size_t n = m_radii.size();
    m_quadraticGrid = m_radii == profileGridRadii(m_radii.back(), int(n));
    m_cumulative.assign(n, 0.0);
    for (size_t k = 0; k + 1 < n; ++k)
        m_cumulative[k + 1] = m_cumulative[k] + partial(k, m_radii[k + 1] - m_radii[k]);
    m_pieces.resize(n);
    for (size_t k = 0; k < n; ++k) {
        Piece& pc = m_pieces[k];
        pc.cumulative = m_cumulative[k];
        pc.r = m_radii[k];
        pc.value = m_values[k];
        pc.slope = k + 1 < n ? (m_values[k + 1] - m_values[k]) / (m_radii[k + 1] - m_radii[k]) : 0;
    }
    const double total = m_cumulative.back();
    if (!(total > 0)) fail("the profile has no energy (R(r) = 0 over the whole table)");
    if (!std::isfinite(total)) fail("the profile's energy is not finite");

    // R_m: the smallest r with ∫0^r = (1 − eps)·total. upper_bound finds the first interval
    // whose end exceeds the target, so an interval of zero energy is never chosen.
    const double target = (1 - eps) * total;
    auto it = std::upper_bound(m_cumulative.begin(), m_cumulative.end(), target);
    m_lastInterval = std::min<size_t>(size_t(it - m_cumulative.begin()) - 1, n - 2);
    const size_t m = m_lastInterval;
    const double t = invert(m_pieces[m], m_radii[m + 1] - m_radii[m], target - m_cumulative[m]);
    m_radiusMax = std::min(m_radii[m] + t, m_radii[m + 1]);
    m_kept = m_cumulative[m] + partial(m, m_radiusMax - m_radii[m]);
    // guide table of sample(): entry j is the last interval k with cumulative[k] <= j/G · kept
    m_guide.assign(n, 0);
    for (size_t j = 0, k = 0; j < m_guide.size(); ++j) {
        const double y = double(j) / double(m_guide.size()) * m_kept;
        while (k < m_lastInterval && m_cumulative[k + 1] <= y)
            ++k;
        m_guide[j] = uint32_t(k);
    }

    // Convergence: the last 1 % of the radius range must hold at most eps of the energy.
    const double rLast = m_radii.back(), rEdge = 0.99 * rLast;
    const size_t ke = intervalOf(rEdge);
    const double beyond = (total - (m_cumulative[ke] + partial(ke, rEdge - m_radii[ke]))) / total;
    if (beyond > eps)
        fail(
            "the energy does not converge within the tabulated range: " +
            core::formatNumber(beyond, 6) + " of it lies in the last 1 % of the radii (r > " +
            core::formatNumber(rEdge, 6) + " mm), more than eps = " + core::formatNumber(eps, 6) +
            "; 1 - eps of the energy is reached only at r = " + core::formatNumber(m_radiusMax, 6) +
            " mm of the table's " + core::formatNumber(rLast, 6) + " mm");
}

double TabulatedRadial::partial(size_t k, double t) const {
    const double a = m_radii[k], h = m_radii[k + 1] - a;
    const double ra = m_values[k], rb = m_values[k + 1];
    const double rt = t >= h ? rb : ra + (rb - ra) * (t / h);
    return t / 6 * (ra * (3 * a + t) + rt * (3 * a + 2 * t));
}

double TabulatedRadial::invert(const Piece& pc, double h, double y) {
    if (y <= 0) return 0;
    const double a = pc.r, ra = pc.value, s = pc.slope;
    const double rh = ra + s * h; // R at the interval's end (h may stop short of r_{k+1})
    // partial(k, t) without its division; every term >= 0, as there
    auto energy = [&](double t) {
        const double rt = ra + s * t;
        return t / 6 * (ra * (3 * a + t) + rt * (3 * a + 2 * t));
    };
    const double whole = energy(h);
    if (y >= whole) return h;
    // First guess: r·R(r) taken as linear between q0 = a·R_a and q1 = (a + h)·R(a + h), whose
    // integral, q0·t + (q1 − q0)·t²/(2h), is inverted in closed form (the quadratic's stable
    // root) at y scaled to that integral's total. Off by O((h/a)²) of h, so Newton's method
    // converges in one or two steps on the profile grid.
    const double q0 = a * ra, q1 = (a + h) * rh;
    const double ys = y * (0.5 * h * (q0 + q1)) / whole;
    const double disc = std::max(0.0, q0 * q0 + 2 * (q1 - q0) * ys / h);
    double lo = 0, hi = h;
    double t = std::clamp(2 * ys / (q0 + std::sqrt(disc)), 0.0, h);
    if (!(t >= 0)) t = h * (y / whole); // 0/0 where q0 = 0 and ys underflows
    for (int i = 0; i < 100; ++i) {
        const double g = energy(t) - y;
        if (g == 0) return t;
        (g > 0 ? hi : lo) = t;
        const double rt = ra + s * t;
        const double d = (a + t) * rt;
        double next = d > 0 ? t - g / d : 0.5 * (lo + hi);
        bool newton = d > 0;
        if (!(next > lo && next < hi)) {
            next = 0.5 * (lo + hi);
            newton = false;
        }
        const double step = std::fabs(next - t), tol = 2e-16 * (a + h);
        if (step <= tol || hi - lo <= tol) return next;
        // Newton's error after this step is about |E''/(2E')|·step² (E'' = R_t + s·(a + t)):
        // when that is below the tolerance, `next` is already as good as one more step
        if (newton && std::fabs(rt + s * (a + t)) * step * step <= 2 * d * tol) return next;
        t = next;
    }
    return t;
}

size_t TabulatedRadial::intervalOf(double r) const {
    if (m_quadraticGrid) { // r_k = rMax (k/(K−1))²: k from the square root, then exact
        const size_t last = m_radii.size() - 2;
        const double t = std::sqrt(std::max(r, 0.0) / m_radii.back()) * double(m_radii.size() - 1);
        size_t k = t >= double(last) ? last : size_t(t);
        while (k > 0 && r < m_radii[k])
            --k;
        while (k < last && r >= m_radii[k + 1])
            ++k;
        return k;
    }
    auto it = std::upper_bound(m_radii.begin(), m_radii.end(), r);
    const size_t k = it == m_radii.begin() ? 0 : size_t(it - m_radii.begin()) - 1;
    return std::min(k, m_radii.size() - 2);
}

double TabulatedRadial::sample(double u) const {
    const double y = std::clamp(u, 0.0, 1.0) * m_kept;
    // the guide table gives the first interval that can hold y; a short scan finds it (the
    // interval of upper_bound: the last k with cumulative[k] <= y)
    const size_t g =
        std::min(size_t(std::clamp(u, 0.0, 1.0) * double(m_guide.size())), m_guide.size() - 1);
    size_t k = m_guide[g];
    while (k < m_lastInterval && m_pieces[k + 1].cumulative <= y)
        ++k;
    const Piece& pc = m_pieces[k];
    const double h = (k == m_lastInterval ? m_radiusMax : m_pieces[k + 1].r) - pc.r;
    return std::min(pc.r + invert(pc, h, y - pc.cumulative), m_radiusMax);
}

double TabulatedRadial::profile(double r) const {
    if (!(r >= 0) || r > m_radii.back()) return 0;
    const size_t k = intervalOf(r);
    const double h = m_radii[k + 1] - m_radii[k], f = std::min((r - m_radii[k]) / h, 1.0);
    return m_values[k] + (m_values[k + 1] - m_values[k]) * f;
}

double TabulatedRadial::pdfArea(double r) const {
    if (!(r >= 0) || r > m_radiusMax) return 0;
    return profile(r) / (2 * std::numbers::pi * m_kept);
}

double TabulatedRadial::cdf(double r) const {
    if (!(r > 0)) return 0;
    if (r >= m_radiusMax) return 1;
    const size_t k = intervalOf(r);
    return std::min((m_cumulative[k] + partial(k, r - m_radii[k])) / m_kept, 1.0);
}

double TabulatedRadial::energyWithin(double r) const {
    if (!(r > 0)) return 0;
    if (r >= m_radii.back()) return totalEnergy();
    const size_t k = intervalOf(r);
    return 2 * std::numbers::pi * (m_cumulative[k] + partial(k, r - m_radii[k]));
}

double TabulatedRadial::totalEnergy() const {
    return 2 * std::numbers::pi * m_cumulative.back();
}
double TabulatedRadial::keptEnergy() const {
    return 2 * std::numbers::pi * m_kept;
}

std::vector<double> profileGridRadii(double rMax, int count) {
    std::vector<double> r(size_t(std::max(count, 0)));
    for (int k = 0; k < count; ++k) {
        const double f = count > 1 ? double(k) / (count - 1) : 0.0;
        r[size_t(k)] = rMax * f * f;
    }
    return r;
}

std::array<TabulatedRadial, 3> tabulateChannels(const std::vector<double>& radii,
                                                const std::vector<glm::dvec3>& values, double eps,
                                                const std::string& name) {
    auto column = [&](int c) {
        std::vector<double> v(values.size());
        for (size_t k = 0; k < values.size(); ++k)
            v[k] = values[k][c];
        return v;
    };
    return {TabulatedRadial(radii, column(0), eps, 0, name),
            TabulatedRadial(radii, column(1), eps, 1, name),
            TabulatedRadial(radii, column(2), eps, 2, name)};
}

} // namespace sampling
