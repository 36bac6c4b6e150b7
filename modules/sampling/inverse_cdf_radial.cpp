// sampling/inverse_cdf_radial: see inverse_cdf_radial.h.
#include "sampling/inverse_cdf_radial.h"

#include "core/core.h"
#include "core/text.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace sampling {

InverseCdfRadial::InverseCdfRadial(const std::vector<double>& radii, double radiusMax,
                                   TabulatedRadial profile, int channel, const std::string& name)
    : m_radiusMax(radiusMax), m_profile(std::move(profile)) {
    const std::string ch = "channel " + std::to_string(channel) + ": ";
    auto fail = [&](const std::string& msg) { throw core::Error(name, 0, ch + msg); };
    if (radii.size() < 2)
        fail("the inverse CDF needs at least 2 knots (it has " + std::to_string(radii.size()) +
             ")");
    for (size_t j = 0; j < radii.size(); ++j)
        if (!(std::isfinite(radii[j]) && radii[j] >= 0))
            fail("radius " + std::to_string(j) + " must be finite and >= 0 (it is " +
                 core::formatNumber(radii[j], 6) + ")");
    if (!(std::isfinite(radiusMax) && radiusMax >= radii.back()))
        fail("R_m (" + core::formatNumber(radiusMax, 6) +
             ") must be finite and >= the last radius " + core::formatNumber(radii.back(), 6));
    const size_t cells = radii.size() - 1;
    m_annulusOfCell.resize(cells);
    m_u.push_back(0.0);
    m_rho.push_back(radii[0]);
    for (size_t j = 1; j <= cells; ++j) {
        m_annulusOfCell[j - 1] = unsigned(m_u.size() - 1);
        if (!(radii[j] > m_rho.back())) continue; // merged into the next annulus
        m_u.push_back(double(j) / double(cells));
        m_rho.push_back(radii[j]);
    }
    if (m_u.size() < 2) fail("every radius is " + core::formatNumber(radii[0], 6));
    m_u.back() = 1.0; // repeated last radii: the last annulus takes their probability
    for (unsigned& a : m_annulusOfCell)
        a = std::min<unsigned>(a, unsigned(m_u.size() - 2));
    m_rho2.resize(m_rho.size());
    for (size_t a = 0; a < m_rho.size(); ++a)
        m_rho2[a] = m_rho[a] * m_rho[a];
    m_density.resize(m_u.size() - 1);
    for (size_t a = 0; a + 1 < m_u.size(); ++a)
        m_density[a] = (m_u[a + 1] - m_u[a]) / (std::numbers::pi * (m_rho2[a + 1] - m_rho2[a]));
}

size_t InverseCdfRadial::annulusOf(double r) const {
    const auto it = std::upper_bound(m_rho.begin(), m_rho.end(), r);
    const size_t k = it == m_rho.begin() ? 0 : size_t(it - m_rho.begin()) - 1;
    return std::min(k, m_density.size() - 1);
}

double InverseCdfRadial::sample(double u) const {
    u = std::clamp(u, 0.0, 1.0);
    const size_t cells = m_annulusOfCell.size();
    const size_t a = m_annulusOfCell[std::min(size_t(u * double(cells)), cells - 1)];
    const double t = std::clamp((u - m_u[a]) / (m_u[a + 1] - m_u[a]), 0.0, 1.0);
    const double r = std::sqrt(m_rho2[a] + t * (m_rho2[a + 1] - m_rho2[a]));
    return std::clamp(r, m_rho[a], m_rho[a + 1]);
}

double InverseCdfRadial::pdfArea(double r) const {
    if (!(r >= m_rho.front()) || r > m_rho.back()) return 0;
    return m_density[annulusOf(r)];
}

double InverseCdfRadial::cdf(double r) const {
    if (!(r > m_rho.front())) return 0;
    if (r >= m_rho.back()) return 1;
    const size_t a = annulusOf(r);
    return std::min(m_u[a] + (r * r - m_rho2[a]) * std::numbers::pi * m_density[a], 1.0);
}

} // namespace sampling
