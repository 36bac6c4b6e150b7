// sampling/channel_pdf_table: see channel_pdf_table.h.
#include "sampling/channel_pdf_table.h"

#include <algorithm>
#include <cmath>

namespace sampling {

std::optional<ChannelPdfTable>
ChannelPdfTable::of(const std::array<const RadialDistribution*, 3>& channels) {
    std::array<const TabulatedRadial*, 3> t{};
    const TabulatedRadial* first = nullptr;
    for (int c = 0; c < 3; ++c) {
        if (!channels[c]) continue;
        t[c] = dynamic_cast<const TabulatedRadial*>(channels[c]);
        if (!t[c]) return std::nullopt;
        if (!first)
            first = t[c];
        else if (t[c] != first && t[c]->radii() != first->radii())
            return std::nullopt;
    }
    if (!first) return std::nullopt;
    ChannelPdfTable table;
    table.m_radii = first->radii();
    const size_t n = table.m_radii.size();
    table.m_rLast = table.m_radii.back();
    table.m_invRLast = 1 / table.m_rLast;
    table.m_quadraticGrid = table.m_radii == profileGridRadii(table.m_rLast, int(n));
    table.m_intervals.resize(n - 1);
    for (size_t k = 0; k + 1 < n; ++k) {
        Interval& iv = table.m_intervals[k];
        iv.r0 = table.m_radii[k];
        const double h = table.m_radii[k + 1] - table.m_radii[k];
        for (int c = 0; c < 3; ++c) {
            if (!t[c]) continue;
            const double norm = 1 / t[c]->keptEnergy(); // 1/E_m,c
            const std::vector<double>& v = t[c]->values();
            iv.v[c] = v[k] * norm;
            iv.slope[c] = (v[k + 1] - v[k]) / h * norm;
        }
    }
    for (int c = 0; c < 3; ++c)
        if (t[c]) table.m_radiusMax[c] = t[c]->radiusMax();
    return table;
}

size_t ChannelPdfTable::intervalOf(double r) const {
    const size_t last = m_radii.size() - 2;
    if (m_quadraticGrid) {
        const double t = std::sqrt(r * m_invRLast) * double(m_radii.size() - 1);
        size_t k = t >= double(last) ? last : size_t(t);
        while (k > 0 && r < m_radii[k])
            --k;
        while (k < last && r >= m_radii[k + 1])
            ++k;
        return k;
    }
    auto it = std::upper_bound(m_radii.begin(), m_radii.end(), r);
    const size_t k = it == m_radii.begin() ? 0 : size_t(it - m_radii.begin()) - 1;
    return std::min(k, last);
}

glm::dvec3 ChannelPdfTable::pdfArea(double r) const {
    glm::dvec3 out(0.0);
    if (!(r >= 0) || r > m_rLast) return out;
    const Interval& iv = m_intervals[intervalOf(r)];
    const double dt = r - iv.r0;
    for (int c = 0; c < 3; ++c)
        if (r <= m_radiusMax[c]) out[c] = iv.v[c] + iv.slope[c] * dt;
    return out;
}

} // namespace sampling
